#include "link_options.hpp"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "command.hpp"
#include "common/layers.hpp"
#include "link/link_advice.hpp"
#include "link/port.hpp"
#include "ops/devicenet.hpp"

namespace lmcfg::cli {

namespace {
// "lmcfg fleet backup": the subcommand's name and its parents', set when the
// subcommand is parsed (one CommonOptions may serve several subcommands).
void name_holder(CLI::App* sub, CommonOptions& o) {
  sub->preparse_callback([sub, &o](std::size_t) {
    std::string name;
    for (const CLI::App* a = sub; a && a->get_parent(); a = a->get_parent())
      name = a->get_name() + (name.empty() ? "" : " ") + name;
    o.holder = "lmcfg " + name;
  });
}
}  // namespace

void add_link_options(CLI::App* sub, CommonOptions& o) {
  name_holder(sub, o);
  sub->add_option(
         "--port", o.port,
         "/dev/ttyUSB0, tcp://host:port (serial gateway; it sets the rate), rfc2217://host:port "
         "(RFC 2217 serial server; the tool sets the rate) or sim:STATE.json (simulated drive)")
      ->required();
  sub->add_option("--baud", o.baud, "baud rate: 4800, 9600, 19200, 38400, 57600, 115200")
      ->capture_default_str();
  sub->add_option("--parity", o.parity, "none, even or odd")->capture_default_str();
  sub->add_option("--stop-bits", o.stop_bits, "1 or 2")->capture_default_str();
  sub->add_option("--id", o.id, "drive MACID, hex (0x11, 11h) or decimal (17)")
      ->capture_default_str();
  sub->add_option("--checksum", o.checksum,
                  "none, add, crc (= crc-ffff), crc-0000 or crc-kermit (reflected)")
      ->capture_default_str();
  sub->add_option("--checksum-coverage", o.checksum_coverage,
                  "bytes the checksum covers: id (ID..last data byte), start (01..last data "
                  "byte) or data (02..last data byte)")
      ->capture_default_str();
  sub->add_option("--response-layout", o.response_layout,
                  "items of the drive's default response (§6.1.1.1): auto (from the answer's "
                  "length), factory, or a list like comm_state,status_word,warn_word,monitoring_1")
      ->capture_default_str();
  sub->add_option("--timeout-ms", o.timeout_ms,
                  "upper bound of an ordinary request's answer deadline; the deadline adapts "
                  "below it to the wire time and the measured round trips (docs/reliability.md)")
      ->capture_default_str();
  sub->add_option("--settle-ms", o.settle_ms,
                  "quiet time awaited after a lost or garbled answer before the next request "
                  "(default: as long as the failed exchange's deadline, at most 500 ms)");
  sub->add_option("--retries", o.retries, "retries of a read after a lost or garbled answer")
      ->capture_default_str();
  sub->add_option("--long-timeout-s", o.long_timeout_s,
                  "deadline of each long operation (defaulting a layer, flash save, reset, MC "
                  "start) in seconds; default 120 (real drives were silent for 30-90 s after "
                  "saves, docs/field.md)");
  sub->add_option("--recover-timeout-s", o.recover_timeout_s,
                  "when a long operation's answer never comes: how long to poll for the drive "
                  "to answer again, in seconds, before reading back what it holds; default 180");
  sub->add_option("--agreeing-reads", o.agreeing_reads,
                  "reads of each value that must agree: auto (1 with a checksum or parity; "
                  "without, 2, and 3 once the line has corrupted an answer) or 1..5 for every "
                  "value (docs/reliability.md: 2 is faster on a noisy line, 3 safer)")
      ->capture_default_str();
  sub->add_option("--trace", o.trace,
                  "write every telegram (CAN: every frame, with its DeviceNet meaning) as "
                  "timestamped hex to FILE");
  sub->add_flag("--verbose", o.verbose,
                "link errors: the protocol detail too, after the advice on what to change");
}

void add_devicenet_options(CLI::App* sub, CommonOptions& o) {
  // A group of their own in --help: only the commands that take DeviceNet
  // controllers (backup, diff, restore, undo) list them.
  const std::string group = "DeviceNet (--port can0 or slcan:/dev/ttyACM0)";
  sub->add_option("--can-bitrate", o.can_bitrate,
                  "DeviceNet (--port can0 or slcan:/dev/ttyACM0): 125000, 250000 or 500000")
      ->capture_default_str()
      ->group(group);
  sub->add_option("--devicenet-macid", o.devicenet_macid,
                  "DeviceNet: the controller's MAC ID, 0..63 (seed 000 controllers)")
      ->group(group);
  sub->add_option("--devicenet-own-macid", o.devicenet_own_macid,
                  "DeviceNet: this tool's MAC ID on the bus, checked for duplicates first")
      ->capture_default_str()
      ->group(group);
  sub->add_option("--devicenet-listen-ms", o.devicenet_listen_ms,
                  "DeviceNet: how long to listen for another node with this tool's MAC ID after "
                  "each of the two duplicate MAC ID checks (DeviceNet: 1 s)")
      ->capture_default_str()
      ->group(group);
  sub->add_option("--devicenet-motors", o.devicenet_motors,
                  "DeviceNet: the controller's motors, e.g. A,B (default: found by probing "
                  "A..D; the controller refuses absent ones with a coded error)")
      ->group(group);
  sub->add_flag("--no-module-values", o.no_module_values,
                "DeviceNet: do not read the encoder and CAM values (60h..6Bh) that need a master "
                "encoder or IO module")
      ->group(group);
  sub->add_option("--io-modules", o.io_modules,
                  "DeviceNet: the controller's IO modules as set up in LinTalk, e.g. "
                  "control-in,addressed-in,status-out,addressed-out (the default)")
      ->group(group);
}

bool is_devicenet(const CommonOptions& o) {
  return link::is_can_port(o.port) || !o.devicenet_macid.empty();
}

void add_output_options(CLI::App* sub, CommonOptions& o) {
  name_holder(sub, o);
  sub->add_flag("--quiet,-q", o.quiet, "no progress output");
  sub->add_flag("--json", o.json, "machine-readable report on stdout");
  sub->add_option(
      "--db", o.db_path,
      "UPID database (default: $LMCFG_UPID_DB, else lmcfg-upid.sqlite next to lmcfg, else "
      "../share/lmcfg/)");
}

namespace {
// Progress of a long operation on stderr: on a terminal every second on one
// line; otherwise one line after 5 s and every 5 s after that (logs).
std::function<void(const std::string&, transport::Millis)> long_wait_reporter(
    const client::ClientOptions& c) {
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const long long def_s = c.defaulting_timeout.count() / 1000,
                  flash_s = c.flash_timeout.count() / 1000,
                  reset_s = c.reset_timeout.count() / 1000,
                  recover_s = c.recover_timeout.count() / 1000;
  return [=](const std::string& what, transport::Millis waited) {
    const long long s = waited.count() / 1000;
    // Client::find_again reports "waiting for drive 11h to answer again after ...".
    const bool recovering = what.rfind("waiting for drive", 0) == 0;
    const long long limit = recovering                                ? recover_s
                            : what.rfind("defaulting", 0) == 0        ? def_s
                            : what.find("flash") != std::string::npos ? flash_s
                                                                      : reset_s;
    const char* option = recovering ? "--recover-timeout-s" : "--long-timeout-s";
    if (tty) {
      std::fprintf(stderr, "\r%s: %lld s (waiting up to %lld s) ", what.c_str(), s, limit);
    } else if (s >= 5 && s % 5 == 0) {
      std::fprintf(stderr, "lmcfg: still %s: %lld s (waiting up to %lld s; %s)\n", what.c_str(), s,
                   limit, option);
    }
  };
}
}  // namespace

Result<link::LinkSpec> link_options(const CommonOptions& o, const std::atomic<bool>* cancel) {
  link::LinkInput in = o;  // the link part, as typed
  in.cancel = cancel;
  LMCFG_ASSIGN_OR_RETURN(auto spec, link::make_link_spec(in));
  // The reporter names the spec's deadlines, so it is added once they are known.
  if (!o.quiet && !o.json) spec.client.on_long_wait = long_wait_reporter(spec.client);
  return spec;
}

void add_reconnect_options(CLI::App* sub, ReconnectOptions& o) {
  sub->add_option("--reconnect-baud", o.baud,
                  "with --include-comm: baud rate to try first after the reset");
  sub->add_option("--reconnect-id", o.id,
                  "with --include-comm: MACID to try first after the reset");
  sub->add_option("--reconnect-checksum", o.checksum,
                  "with --include-comm: checksum to try first after the reset");
}

Result<link::RelinkOverrides> relink_overrides(const ReconnectOptions& o) {
  link::RelinkOverrides r;
  if (!o.baud.empty()) {
    transport::SerialSettings s;
    auto b = parse_number(o.baud, false);
    s.baud = b ? *b : 0;
    if (auto v = transport::validate(s); !v.ok())
      return Error(Errc::invalid_argument, "--reconnect-baud: " + v.error().message);
    r.baud = s.baud;
  }
  if (!o.id.empty()) {
    auto id = parse_number(o.id, false);
    if (!id || *id > 0xFF)
      return Error(Errc::invalid_argument,
                   "--reconnect-id '" + o.id + "' is not a MACID 0..255 (0x00..0xFF)");
    r.macid = static_cast<std::uint8_t>(*id);
  }
  if (!o.checksum.empty()) {
    auto c = link::parse_checksum(o.checksum);
    if (!c.ok()) return Error(Errc::invalid_argument, "--reconnect-checksum: " + c.error().message);
    r.checksum = *c;
  }
  return r;
}

int SessionHandle::fail(const char* command, const Error& e) const {
  if (session_ && link::settings_suspect(*session_, e)) {
    if (auto advice = link::link_advice(*session_, port_)) {
      if (verbose_) *advice += " (detail: " + e.message + ")";
      std::fprintf(stderr, "lmcfg %s: %s\n", command, advice->c_str());
      return exit_code_for(e);
    }
  }
  return cli::fail(command, e);
}

Result<SessionHandle> open_link(const CommonOptions& o, const std::atomic<bool>* cancel) {
  if (is_devicenet(o)) {
    return Error(Errc::not_supported,
                 "--port " + o.port +
                     " names a DeviceNet controller: backup, diff, restore and undo support "
                     "those; this command is for LinRS drives");
  }
  LMCFG_ASSIGN_OR_RETURN(const auto spec, link_options(o, cancel));
  LMCFG_ASSIGN_OR_RETURN(auto s, link::open_session(spec));
  // A USB adapter whose latency timer stays above 2 ms: said once, with the fix.
  if (const auto* lat = s->low_latency(); lat && !lat->advice.empty() && !o.quiet)
    std::fprintf(stderr, "lmcfg: %s\n", lat->advice.c_str());
  return SessionHandle(std::move(s), o.port, o.verbose);
}

db::Database load_database(const CommonOptions& o) {
  auto r = o.db_path.empty() ? db::Database::open_default() : db::Database::open(o.db_path);
  if (!r.ok()) {
    if (!o.quiet)
      std::fprintf(stderr, "lmcfg: warning: UPID database not loaded (%s); showing raw values\n",
                   r.error().message.c_str());
    return db::Database{};
  }
  return std::move(r).value();
}

ProgressBar::ProgressBar(const CommonOptions& o)
    : shown_(!o.quiet && !o.json && ::isatty(STDERR_FILENO)) {}

ops::Progress ProgressBar::callback() {
  if (!shown_) return {};
  return [this](const std::string& phase, std::size_t done, std::size_t total) {
    if (phase != phase_) {
      phase_ = phase;
      start_ = std::chrono::steady_clock::now();
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char line[160];
    if (total > 0) {
      const int width = 30;
      const int filled = static_cast<int>(static_cast<double>(width) * static_cast<double>(done) /
                                          static_cast<double>(total));
      std::string bar(static_cast<std::size_t>(std::min(filled, width)), '#');
      bar.resize(width, '.');
      const double eta = done > 0 ? elapsed * static_cast<double>(total - std::min(done, total)) /
                                        static_cast<double>(done)
                                  : 0.0;
      std::snprintf(line, sizeof line, "\r%-28.28s [%s] %zu/%zu ETA %.0fs ", phase.c_str(),
                    bar.c_str(), done, total, eta);
    } else {
      std::snprintf(line, sizeof line, "\r%-28.28s %zu ", phase.c_str(), done);
    }
    std::fputs(line, stderr);
    drawn_ = true;
  };
}

void ProgressBar::end() {
  if (drawn_ && shown_) std::fputs("\n", stderr);
  drawn_ = false;
}

Result<std::array<bool, 4>> parse_layers(const std::string& text) {
  std::array<bool, 4> on{false, false, false, false};
  std::size_t pos = 0;
  while (pos <= text.size()) {
    auto comma = text.find(',', pos);
    std::string item =
        text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    auto layer = layers::from_name(item);
    if (!layer)
      return Error(Errc::invalid_argument,
                   "--layers: '" + item + "' is not one of os, mc, intf, appl");
    on[static_cast<std::size_t>(*layer - 1)] = true;
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return on;
}

Result<void> check_output_path(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  if (path == "-") return {};
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return Error(Errc::invalid_argument, "output '" + path + "' is a directory; name a file");
  const fs::path parent = fs::path(path).parent_path();
  const std::string dir = parent.empty() ? "." : parent.string();
  if (!fs::exists(dir, ec))
    return Error(Errc::invalid_argument, option + " '" + path + "': directory '" + dir +
                                             "' does not exist; create it or name another path");
  if (!fs::is_directory(dir, ec))
    return Error(Errc::invalid_argument,
                 option + " '" + path + "': '" + dir + "' is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    return Error(Errc::invalid_argument, option + " '" + path + "': directory '" + dir +
                                             "' is not writable (" + std::strerror(errno) + ")");
  return {};
}

int exit_code_for(const Error& e) {
  // One exit code per error class (common/result.hpp, class_of).
  const auto c = class_of(e.code);
  if (!c) return e.code == Errc::ok ? kOk : kInternal;
  switch (*c) {
    case ErrorClass::link_failure:
    case ErrorClass::bad_answer:
    case ErrorClass::link_down:
      return kCommFailure;
    case ErrorClass::drive_refusal:
      return kDriveRefused;
    case ErrorClass::bad_input:
      return kInvalidInput;
    case ErrorClass::plan_refused:
      return kPlanRefused;
    case ErrorClass::verify_mismatch:
      return kVerifyMismatch;
    case ErrorClass::interrupted:
      return kInterrupted;
  }
  return kInternal;
}

int fail(const char* command, const Error& e) {
  std::fprintf(stderr, "lmcfg %s: %s\n", command, e.message.c_str());
  return exit_code_for(e);
}

}  // namespace lmcfg::cli
