// RFC 2217 client: the Telnet codec (pure, on bytes) and the socket transport.
#include "transport/rfc2217.hpp"

#include <algorithm>

#include "transport/pty.hpp"

namespace lmcfg::transport {
namespace rfc2217 {

std::string command_name(std::uint8_t client_code) {
  switch (static_cast<Command>(client_code)) {
    case Command::signature:
      return "SIGNATURE";
    case Command::set_baudrate:
      return "SET-BAUDRATE";
    case Command::set_datasize:
      return "SET-DATASIZE";
    case Command::set_parity:
      return "SET-PARITY";
    case Command::set_stopsize:
      return "SET-STOPSIZE";
    case Command::set_control:
      return "SET-CONTROL";
    case Command::notify_linestate:
      return "NOTIFY-LINESTATE";
    case Command::notify_modemstate:
      return "NOTIFY-MODEMSTATE";
    case Command::flowcontrol_suspend:
      return "FLOWCONTROL-SUSPEND";
    case Command::flowcontrol_resume:
      return "FLOWCONTROL-RESUME";
    case Command::set_linestate_mask:
      return "SET-LINESTATE-MASK";
    case Command::set_modemstate_mask:
      return "SET-MODEMSTATE-MASK";
    case Command::purge_data:
      return "PURGE-DATA";
  }
  return "code " + std::to_string(client_code);
}

void Decoder::feed(ByteView in, Bytes& data, std::vector<Event>& events) {
  // The byte after an IAC.
  const auto command = [&](std::uint8_t b) {
    // RFC 856: "IAC followed by IAC ... stands for the 8 bit binary data with
    // the decimal value 255".
    if (b == kIAC) {
      data.push_back(b);
      state_ = State::data;
    } else if (b >= kWILL && b <= kDONT) {
      verb_ = b;
      state_ = State::option;
    } else if (b == kSB) {
      state_ = State::sb_option;
    } else {
      // NOP, DM, BRK, IP, AO, AYT, EC, EL, GA and a stray SE: two bytes, no data.
      events.push_back(Event{Event::Kind::command, b, 0, {}});
      state_ = State::data;
    }
  };
  for (const std::uint8_t b : in) {
    switch (state_) {
      case State::data:
        if (b == kIAC)
          state_ = State::iac;
        else
          data.push_back(b);
        break;
      case State::iac:
        command(b);
        break;
      case State::option:
        events.push_back(Event{Event::Kind::negotiation, verb_, b, {}});
        state_ = State::data;
        break;
      case State::sb_option:
        sb_ = Event{Event::Kind::subnegotiation, kSB, b, {}};
        state_ = State::sb;
        break;
      case State::sb:
        if (b == kIAC)
          state_ = State::sb_iac;
        else
          sb_.payload.push_back(b);
        break;
      case State::sb_iac:
        // RFC 855: "IAC SB <option code> <parameters> IAC SE"; a 255 among the
        // parameters is doubled "in accordance with the general TELNET rules".
        if (b == kIAC) {
          sb_.payload.push_back(b);
          state_ = State::sb;
          break;
        }
        events.push_back(std::move(sb_));
        sb_ = Event{};
        state_ = State::data;
        // Any command but SE inside a subnegotiation is not allowed: it ends
        // the subnegotiation and is taken as the command it is, rather than
        // swallowing the data that follows.
        if (b != kSE) command(b);
        break;
    }
  }
}

Bytes escape_data(ByteView data) {
  Bytes out;
  out.reserve(data.size() + 4);
  for (const std::uint8_t b : data) {
    out.push_back(b);
    if (b == kIAC) out.push_back(kIAC);
  }
  return out;
}

Bytes encode_negotiation(std::uint8_t verb, std::uint8_t option) { return {kIAC, verb, option}; }

Bytes encode_command(Command code, ByteView value) {
  Bytes out{kIAC, kSB, kComPort, static_cast<std::uint8_t>(code)};
  const Bytes v = escape_data(value);
  out.insert(out.end(), v.begin(), v.end());
  out.push_back(kIAC);
  out.push_back(kSE);
  return out;
}

Bytes baud_value(unsigned baud) {
  // RFC 2217 SET-BAUDRATE: "The value is four octets (4 bytes). The value is
  // represented in network standard format."
  return {static_cast<std::uint8_t>(baud >> 24), static_cast<std::uint8_t>(baud >> 16),
          static_cast<std::uint8_t>(baud >> 8), static_cast<std::uint8_t>(baud)};
}

std::uint8_t parity_value(Parity p) {
  // RFC 2217 SET-PARITY: 1 NONE, 2 ODD, 3 EVEN, 4 MARK, 5 SPACE.
  switch (p) {
    case Parity::none:
      return 1;
    case Parity::odd:
      return 2;
    case Parity::even:
      return 3;
  }
  return 1;
}

std::uint8_t stopsize_value(unsigned stop_bits) {
  // RFC 2217 SET-STOPSIZE: 1 = 1 stop bit, 2 = 2, 3 = 1.5.
  return stop_bits == 2 ? 2 : 1;
}

std::string value_text(Command code, ByteView value) {
  const auto one = [&](const char* const* names, std::size_t n) -> std::string {
    if (value.size() == 1 && value[0] < n && names[value[0]] != nullptr) return names[value[0]];
    return "value " + to_hex(value);
  };
  switch (code) {
    case Command::set_baudrate:
      if (value.size() == 4) {
        const std::uint32_t v = (std::uint32_t{value[0]} << 24) | (std::uint32_t{value[1]} << 16) |
                                (std::uint32_t{value[2]} << 8) | value[3];
        return std::to_string(v);
      }
      break;
    case Command::set_datasize:
      if (value.size() == 1) return std::to_string(value[0]) + " data bits";
      break;
    case Command::set_parity: {
      static const char* const names[] = {"(query)", "none", "odd", "even", "mark", "space"};
      return one(names, std::size(names));
    }
    case Command::set_stopsize: {
      static const char* const names[] = {"(query)", "1 stop bit", "2 stop bits", "1.5 stop bits"};
      return one(names, std::size(names));
    }
    case Command::set_control: {
      static const char* const names[] = {"(query)", "no flow control", "XON/XOFF flow control",
                                          "hardware flow control"};
      return one(names, std::size(names));
    }
    default:
      break;
  }
  return "value " + to_hex(value);
}

Result<void> check_confirmation(Command asked, ByteView asked_value, ByteView payload) {
  const auto code = static_cast<std::uint8_t>(asked);
  const std::string name = command_name(code);
  // RFC 2217 (paraphrase): the access server answers each command with the
  // same command code plus 100 and the value now in effect.
  if (payload.empty() || payload[0] != code + kServerOffset) {
    return Error(Errc::unexpected_response,
                 "the server answered " + name + " with " +
                     (payload.empty() ? std::string("an empty subnegotiation")
                                      : "code " + std::to_string(payload[0])) +
                     ", expected code " + std::to_string(code + kServerOffset));
  }
  const ByteView got = payload.subspan(1);
  if (got.size() != asked_value.size()) {
    return Error(Errc::unexpected_response,
                 "the server confirmed " + name + " with " + std::to_string(got.size()) +
                     " value bytes, expected " + std::to_string(asked_value.size()));
  }
  if (!std::equal(got.begin(), got.end(), asked_value.begin())) {
    return Error(Errc::unexpected_response, "the server confirmed " + name + " " +
                                                value_text(asked, got) + ", asked " +
                                                value_text(asked, asked_value));
  }
  return {};
}

namespace {
bool we_support(std::uint8_t option) {
  return option == kBinary || option == kSuppressGoAhead || option == kComPort;
}
bool they_may(std::uint8_t option) { return option == kBinary || option == kSuppressGoAhead; }
}  // namespace

Bytes Negotiator::start() {
  // RFC 2217: the client sends "IAC WILL COM-PORT-OPTION" and the access
  // server answers DO or DONT. BINARY (RFC 856) both ways so that CR and NUL
  // pass unchanged; SUPPRESS-GO-AHEAD (RFC 858) both ways, as a full-duplex line.
  Bytes out;
  for (const std::uint8_t o : {kComPort, kBinary, kSuppressGoAhead}) {
    ours_[o] = Side::asked;
    const Bytes n = encode_negotiation(kWILL, o);
    out.insert(out.end(), n.begin(), n.end());
  }
  for (const std::uint8_t o : {kBinary, kSuppressGoAhead}) {
    theirs_[o] = Side::asked;
    const Bytes n = encode_negotiation(kDO, o);
    out.insert(out.end(), n.begin(), n.end());
  }
  return out;
}

Bytes Negotiator::answer(std::uint8_t verb, std::uint8_t option) {
  // RFC 854: "If a party receives what appears to be a request to enter some
  // mode it is already in, the request should not be acknowledged. This
  // non-response is essential to prevent endless loops in the negotiation."
  // An answer to our own request is not acknowledged either.
  switch (verb) {
    case kDO: {
      if (!we_support(option)) return encode_negotiation(kWONT, option);
      Side& s = ours_[option];
      if (s == Side::on) return {};
      const bool was_asked = s == Side::asked;
      s = Side::on;
      return was_asked ? Bytes{} : encode_negotiation(kWILL, option);
    }
    case kDONT: {
      Side& s = ours_[option];
      if (s == Side::asked) s = Side::refused;
      if (s != Side::on) return {};
      s = Side::off;
      return encode_negotiation(kWONT, option);
    }
    case kWILL: {
      if (!they_may(option)) return encode_negotiation(kDONT, option);
      Side& s = theirs_[option];
      if (s == Side::on) return {};
      const bool was_asked = s == Side::asked;
      s = Side::on;
      return was_asked ? Bytes{} : encode_negotiation(kDO, option);
    }
    case kWONT: {
      Side& s = theirs_[option];
      if (s == Side::asked) s = Side::refused;
      if (s != Side::on) return {};
      s = Side::off;
      return encode_negotiation(kDONT, option);
    }
    default:
      return {};
  }
}

}  // namespace rfc2217

namespace {

using namespace rfc2217;

double byte_time(const SerialSettings& s) {
  return 1e6 * bits_per_byte(s) / static_cast<double>(s.baud);
}

class Rfc2217Transport final : public FdTransport {
 public:
  Rfc2217Transport(UniqueFd fd, std::string where, const SerialSettings& s, Millis timeout)
      : FdTransport(std::move(fd), describe_line(where, s), byte_time(s)),
        where_(std::move(where)),
        settings_(s),
        timeout_(timeout) {}

  // Option negotiation, then the line settings; every step within the timeout.
  Result<void> start() {
    LMCFG_TRY(FdTransport::write(negotiator_.start()));
    const auto deadline = Clock::now() + timeout_;
    LMCFG_TRY(pump_until(deadline, [&] {
      return negotiator_.ours(kComPort) == Negotiator::Side::on ||
             negotiator_.ours(kComPort) == Negotiator::Side::refused;
    }));
    if (negotiator_.ours(kComPort) == Negotiator::Side::refused) {
      return Error(Errc::not_supported,
                   describe() +
                       ": the server refused COM-PORT-OPTION (IAC DONT 44): it does not "
                       "speak RFC 2217, so the serial line's settings cannot be set from here");
    }
    if (negotiator_.ours(kComPort) != Negotiator::Side::on) {
      return Error(Errc::timeout, describe() +
                                      ": the server did not accept COM-PORT-OPTION "
                                      "(no IAC DO 44) within " +
                                      std::to_string(timeout_.count()) +
                                      " ms; is it a raw TCP port rather than RFC 2217?");
    }
    return apply(settings_);
  }

  Result<void> write(ByteView bytes) override { return FdTransport::write(escape_data(bytes)); }

  Result<Bytes> read_some(Millis timeout) override {
    const auto deadline = Clock::now() + std::max(timeout, Millis(0));
    while (data_.empty()) {
      LMCFG_ASSIGN_OR_RETURN(Bytes chunk, FdTransport::read_some(left(deadline)));
      if (chunk.empty()) break;  // the deadline passed without a byte
      LMCFG_TRY(take(chunk));
      if (Clock::now() >= deadline) break;
    }
    Bytes out;
    out.swap(data_);
    return out;
  }

  void discard_input() override {
    // RFC 2217 PURGE-DATA: "1 Purge access server receive data buffer", the
    // bytes it read from the serial line and has not sent yet. Its
    // confirmation comes later and is ignored; the server handles the purge
    // before any data written after it, so a retried telegram's answer is kept.
    const Bytes purge{kPurgeReceiveBuffer};
    (void)FdTransport::write(encode_command(Command::purge_data, purge));
    // Drain what arrived through the decoder (commands may be split) and drop the data.
    for (int i = 0; i < 256; ++i) {
      auto r = FdTransport::read_some(Millis(0));
      if (!r.ok() || r->empty()) break;
      if (!take(*r).ok()) break;
    }
    data_.clear();
  }

  Result<void> reconfigure(const SerialSettings& in) override {
    SerialSettings s = in;
    s.device.clear();
    LMCFG_TRY(validate(s));
    LMCFG_TRY(apply(s));
    return {};
  }

 private:
  static std::string describe_line(const std::string& where, const SerialSettings& s) {
    return "rfc2217 " + where + " " + format_settings(s);
  }
  static Millis left(Clock::time_point deadline) {
    const auto now = Clock::now();
    return now >= deadline ? Millis(0) : std::chrono::ceil<Millis>(deadline - now);
  }

  // Decodes one chunk from the server: data to data_, negotiations answered,
  // COM-PORT-OPTION answers matched with what waits for a confirmation; the
  // server's notifications (NOTIFY-LINESTATE, NOTIFY-MODEMSTATE, flow control,
  // SIGNATURE) and other commands are dropped.
  Result<void> take(ByteView chunk) {
    std::vector<Event> events;
    decoder_.feed(chunk, data_, events);
    Bytes replies;
    for (const Event& e : events) {
      if (e.kind == Event::Kind::negotiation) {
        const Bytes a = negotiator_.answer(e.verb, e.option);
        replies.insert(replies.end(), a.begin(), a.end());
      } else if (e.kind == Event::Kind::subnegotiation && e.option == kComPort &&
                 !e.payload.empty()) {
        for (auto& w : waiting_) {
          if (w.answered || e.payload[0] != static_cast<std::uint8_t>(w.code) + kServerOffset)
            continue;
          w.answered = true;
          auto checked = check_confirmation(w.code, w.value, e.payload);
          if (!checked.ok() && !first_error_)
            first_error_ = Error(checked.error().code, describe() + ": " + checked.error().message);
          break;
        }
      }
    }
    if (!replies.empty()) LMCFG_TRY(FdTransport::write(replies));
    return {};
  }

  template <class Done>
  Result<void> pump_until(Clock::time_point deadline, Done done) {
    while (!done()) {
      LMCFG_ASSIGN_OR_RETURN(Bytes chunk, FdTransport::read_some(left(deadline)));
      if (!chunk.empty()) LMCFG_TRY(take(chunk));
      if (Clock::now() >= deadline) break;
    }
    return {};
  }

  // Sends the four settings and no flow control, waits for every confirmation.
  Result<void> apply(const SerialSettings& s) {
    waiting_ = {
        {Command::set_baudrate, baud_value(s.baud)},
        {Command::set_datasize, Bytes{kDataSize8}},
        {Command::set_parity, Bytes{parity_value(s.parity)}},
        {Command::set_stopsize, Bytes{stopsize_value(s.stop_bits)}},
        {Command::set_control, Bytes{kControlNoFlowControl}},
    };
    first_error_.reset();
    Bytes out;
    for (const auto& w : waiting_) {
      const Bytes c = encode_command(w.code, w.value);
      out.insert(out.end(), c.begin(), c.end());
    }
    LMCFG_TRY(FdTransport::write(out));
    const auto deadline = Clock::now() + timeout_;
    auto all_answered = [&] {
      return std::all_of(waiting_.begin(), waiting_.end(),
                         [](const Waiting& w) { return w.answered; });
    };
    LMCFG_TRY(pump_until(deadline, all_answered));
    const auto missing = std::find_if(waiting_.begin(), waiting_.end(),
                                      [](const Waiting& w) { return !w.answered; });
    // A refused value is the more useful message even when another is missing.
    if (first_error_) return *first_error_;
    if (missing != waiting_.end()) {
      const auto code = static_cast<std::uint8_t>(missing->code);
      return Error(Errc::timeout, describe() + ": no confirmation of " + command_name(code) + " " +
                                      value_text(missing->code, missing->value) + " (code " +
                                      std::to_string(code + kServerOffset) +
                                      ") from the server within " +
                                      std::to_string(timeout_.count()) + " ms");
    }
    // RFC 856: without BINARY the server may change CR and NUL in the data.
    if (negotiator_.ours(kBinary) == Negotiator::Side::refused ||
        negotiator_.theirs(kBinary) == Negotiator::Side::refused) {
      return Error(Errc::not_supported, describe() +
                                            ": the server refused TRANSMIT-BINARY (RFC 856); LinRS "
                                            "telegrams are binary and would not pass unchanged");
    }
    settings_ = s;
    set_line_description(describe_line(where_, s), byte_time(s));
    return {};
  }

  struct Waiting {
    Command code;
    Bytes value;
    bool answered = false;
  };

  std::string where_;
  SerialSettings settings_;
  Millis timeout_;
  Decoder decoder_;
  Negotiator negotiator_;
  Bytes data_;  // decoded data not handed out yet
  std::vector<Waiting> waiting_;
  std::optional<Error> first_error_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_rfc2217(const std::string& host, std::uint16_t port,
                                                const SerialSettings& s, Millis connect_timeout) {
  SerialSettings line = s;
  line.device.clear();
  LMCFG_TRY(validate(line));
  LMCFG_ASSIGN_OR_RETURN(auto c, connect_tcp(host, port, connect_timeout, "rfc2217"));
  auto t = std::make_unique<Rfc2217Transport>(std::move(c.fd), c.where, line, connect_timeout);
  LMCFG_TRY(t->start());
  return std::unique_ptr<Transport>(std::move(t));
}

}  // namespace lmcfg::transport
