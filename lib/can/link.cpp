#include "can/link.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

namespace lmcfg::can {
namespace {

using Clock = std::chrono::steady_clock;

class SlcanLink final : public Link {
 public:
  SlcanLink(std::unique_ptr<transport::Transport> serial, SlcanOptions opt)
      : serial_(std::move(serial)), opt_(opt) {}
  ~SlcanLink() override { (void)serial_->write(as_bytes(slcan::kClose)); }

  // "C" first (an open channel from an earlier run refuses "Sn"); its answer
  // does not matter. "V" (the version, when the adapter tells it). Then the
  // bit rate and "O": a BEL is a refusal; an adapter that answered neither
  // "C" nor "V" is one that answers no command (slcan leaves open whether an
  // adapter acknowledges), so its
  // silence is not waited for.
  Result<void> open() {
    LMCFG_TRY(serial_->write(as_bytes(slcan::kClose)));
    (void)await_ack("C", transport::Millis(100), true);
    bool answered = acks_ + bells_ > 0;
    serial_->discard_input();
    decoder_.reset();
    last_unknown_.clear();
    bells_ = 0;
    LMCFG_TRY(serial_->write(as_bytes("V\r")));
    const auto until = Clock::now() + opt_.ack_timeout;
    while (bells_ == 0 && !(last_unknown_.size() > 1 && last_unknown_[0] == 'V')) {
      const auto left = std::chrono::duration_cast<transport::Millis>(until - Clock::now());
      if (left.count() <= 0) break;
      LMCFG_TRY(pump(left));
    }
    if (last_unknown_.size() > 1 && last_unknown_[0] == 'V') version_ = last_unknown_.substr(1);
    answered = answered || bells_ > 0 || !version_.empty();
    silent_ = !answered;
    LMCFG_ASSIGN_OR_RETURN(auto rate, slcan::bitrate_command(opt_.bitrate));
    LMCFG_TRY(command(rate));
    return command(std::string(slcan::kOpen));
  }

  // Not waited for unless expect_transmit_ack: the Linux slcan driver and
  // python-can never wait, and adapters differ (CR, "z", or nothing; slcan
  // leaves it open). Acknowledgements that come are read and dropped.
  Result<void> send(const Frame& f) override {
    LMCFG_TRY(validate(f));
    const std::string line = slcan::encode(f);
    LMCFG_TRY(serial_->write(as_bytes(line)));
    if (!opt_.expect_transmit_ack || silent_) return {};
    return await_ack(line.substr(0, line.size() - 1), opt_.ack_timeout, false);
  }

  Result<std::optional<Frame>> receive(transport::Millis timeout) override {
    const auto until = Clock::now() + timeout;
    while (frames_.empty()) {
      const auto left = std::chrono::duration_cast<transport::Millis>(until - Clock::now());
      if (left.count() <= 0) return std::optional<Frame>();
      LMCFG_TRY(pump(left));
    }
    Frame f = frames_.front();
    frames_.pop_front();
    return std::optional<Frame>(f);
  }

  Result<std::optional<std::uint8_t>> status_flags() override {
    last_unknown_.clear();
    bells_ = 0;
    LMCFG_TRY(serial_->write(as_bytes(slcan::kReadStatus)));
    const auto until = Clock::now() + opt_.ack_timeout;
    const auto is_flags = [](const std::string& l) {
      return l.size() == 3 && l[0] == 'F' && std::isxdigit(static_cast<unsigned char>(l[1])) &&
             std::isxdigit(static_cast<unsigned char>(l[2]));
    };
    while (!is_flags(last_unknown_)) {
      const auto left = std::chrono::duration_cast<transport::Millis>(until - Clock::now());
      if (left.count() <= 0 || bells_ > 0) {
        bells_ = 0;
        return std::optional<std::uint8_t>();  // an adapter without "F"
      }
      LMCFG_TRY(pump(left));
    }
    const auto flags = std::stoul(last_unknown_.substr(1), nullptr, 16);
    return std::optional<std::uint8_t>(static_cast<std::uint8_t>(flags));
  }

  std::string describe() const override {
    std::string d =
        "slcan " + serial_->describe() + " " + std::to_string(opt_.bitrate / 1000) + " kbit/s";
    if (!version_.empty()) d += " (adapter version " + version_ + ")";
    if (silent_) d += " (an adapter that answers no command)";
    return d;
  }

 private:
  Result<void> command(const std::string& line) {
    LMCFG_TRY(serial_->write(as_bytes(line)));
    if (silent_) return {};
    return await_ack(line.substr(0, line.size() - 1), opt_.ack_timeout, false);
  }

  // Reads once; frames are queued, acknowledgements and bells counted.
  Result<void> pump(transport::Millis timeout) {
    LMCFG_ASSIGN_OR_RETURN(auto bytes, serial_->read_some(timeout));
    for (auto& e : decoder_.feed(bytes)) {
      if (auto* f = std::get_if<Frame>(&e)) {
        frames_.push_back(*f);
      } else if (std::holds_alternative<slcan::Ack>(e)) {
        ++acks_;
      } else if (std::holds_alternative<slcan::Bell>(e)) {
        ++bells_;
      } else {
        last_unknown_ = std::get<slcan::Unknown>(e).line;
      }
    }
    return {};
  }

  Result<void> await_ack(const std::string& what, transport::Millis timeout, bool quiet) {
    acks_ = bells_ = 0;
    const auto until = Clock::now() + timeout;
    while (acks_ == 0 && bells_ == 0) {
      const auto left = std::chrono::duration_cast<transport::Millis>(until - Clock::now());
      if (left.count() <= 0) {
        if (quiet) return {};
        return Error(Errc::timeout,
                     serial_->describe() + ": the slcan adapter did not answer '" + what +
                         "' within " + std::to_string(timeout.count()) +
                         " ms (is it an slcan adapter? " +
                         (last_unknown_.empty() ? std::string("it sent nothing")
                                                : "it sent '" + last_unknown_ + "'") +
                         ")");
      }
      LMCFG_TRY(pump(left));
    }
    if (bells_ != 0 && !quiet) {
      return Error(Errc::drive_refused,
                   serial_->describe() + ": the slcan adapter refused '" + what + "' (BEL)");
    }
    return {};
  }

  std::unique_ptr<transport::Transport> serial_;
  SlcanOptions opt_;
  slcan::Decoder decoder_;
  std::deque<Frame> frames_;
  unsigned acks_ = 0, bells_ = 0;
  std::string last_unknown_;
  std::string version_;  // "V" answered: "1013"
  bool silent_ = false;  // answered neither "C" nor "V"
};

}  // namespace

Result<std::unique_ptr<Link>> open_slcan(std::unique_ptr<transport::Transport> serial,
                                         const SlcanOptions& opt) {
  auto link = std::make_unique<SlcanLink>(std::move(serial), opt);
  LMCFG_TRY(link->open());
  return std::unique_ptr<Link>(std::move(link));
}

void TraceLink::trace(const Frame& f, bool tx) {
  std::string line = std::string(tx ? "TX " : "RX ") + can::describe(f);
  if (annotate_) {
    const auto meaning = annotate_(f, tx);
    if (!meaning.empty()) line += "  " + meaning;
  }
  sink_(line);
}

Result<void> TraceLink::send(const Frame& f) {
  trace(f, true);
  return inner_->send(f);
}

Result<std::optional<Frame>> TraceLink::receive(transport::Millis timeout) {
  LMCFG_ASSIGN_OR_RETURN(auto f, inner_->receive(timeout));
  if (f) trace(*f, false);
  return f;
}

}  // namespace lmcfg::can
