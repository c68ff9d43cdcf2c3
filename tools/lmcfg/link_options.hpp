#pragma once
// Options every drive-facing subcommand shares (README): link, output mode,
// database; the mapping from library errors to the documented exit codes.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "common/result.hpp"
#include "db/database.hpp"
#include "link/relink.hpp"
#include "link/session.hpp"
#include "link/spec.hpp"
#include "ops/backup.hpp"

namespace lmcfg::cli {

// The link settings as typed (link::LinkInput: --port ... --trace; its holder,
// "lmcfg <subcommand>" for the port's lock, is set when the subcommand is
// parsed by add_link_options, add_output_options) and the options every
// subcommand shares.
struct CommonOptions : link::LinkInput {
  bool quiet = false;
  bool json = false;
  bool verbose = false;  // link errors keep their protocol detail
  std::string db_path;
  // DeviceNet controllers (seed 000) behind a CAN link (--port can0 / slcan:DEV).
  unsigned can_bitrate = 125000;
  std::string devicenet_macid;  // "" = not given
  unsigned devicenet_own_macid = 62;
  int devicenet_listen_ms = 1000;  // after each duplicate MAC ID check request
  std::string io_modules;          // "" = the default layout
  std::string devicenet_motors;    // "" = detect by probing A..D
  bool no_module_values = false;
};

// --port, --baud, --parity, --stop-bits, --id, --checksum, --checksum-coverage,
// --timeout-ms, --settle-ms, --retries, --long-timeout-s, --agreeing-reads, --trace,
// --verbose.
void add_link_options(CLI::App* sub, CommonOptions& o);
// --can-bitrate, --devicenet-macid, --devicenet-own-macid, --devicenet-listen-ms,
// --devicenet-motors, --no-module-values, --io-modules: for the commands that
// take DeviceNet controllers (backup, diff, restore, undo), in a --help group.
void add_devicenet_options(CLI::App* sub, CommonOptions& o);
// True when the options name a DeviceNet controller: a CAN port or --devicenet-macid.
bool is_devicenet(const CommonOptions& o);
// --quiet, --json, --db.
void add_output_options(CLI::App* sub, CommonOptions& o);

// The command's one link specification (link::make_link_spec: baud 0, ID 300
// ... are refused with a message), with the progress of long waits on stderr
// unless --quiet or --json, and `cancel` (a writing command's interrupt flag)
// for its client.
Result<link::LinkSpec> link_options(const CommonOptions& o,
                                    const std::atomic<bool>* cancel = nullptr);

// A command's open link, owned by its run: the session, and what fail() needs
// to advise on a link failure (the --port text, --verbose).
class SessionHandle {
 public:
  SessionHandle() = default;
  SessionHandle(std::unique_ptr<link::Session> s, std::string port, bool verbose)
      : session_(std::move(s)), port_(std::move(port)), verbose_(verbose) {}
  link::Session* operator->() const { return session_.get(); }
  link::Session& operator*() const { return *session_; }
  explicit operator bool() const { return session_ != nullptr; }
  // fail(command, e), except that a link failure before the drive ever
  // answered is replaced by advice naming the likely wrong setting
  // (link::link_advice); --verbose appends the protocol detail.
  int fail(const char* command, const Error& e) const;

 private:
  std::unique_ptr<link::Session> session_;
  std::string port_;
  bool verbose_ = false;
};
Result<SessionHandle> open_link(const CommonOptions& o, const std::atomic<bool>* cancel = nullptr);

// The database, or an empty one (db::Database::is_empty()) with a warning on
// stderr: a missing database makes output less readable, never wrong.
db::Database load_database(const CommonOptions& o);

// A progress bar on stderr when it is a terminal and not --quiet or --json
// (else nothing), owned by the run that shows it.
class ProgressBar {
 public:
  explicit ProgressBar(const CommonOptions& o);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  // The library's progress callback drawing this bar (empty when not shown);
  // valid while the bar lives.
  ops::Progress callback();
  // Ends a drawn bar's line.
  void end();

 private:
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::string phase_;
  bool drawn_ = false;
};

// --reconnect-baud, --reconnect-id, --reconnect-checksum (restore --include-comm):
// the link settings to try first after the drive's reset. Empty strings = not given.
struct ReconnectOptions {
  std::string baud, id, checksum;
};
void add_reconnect_options(CLI::App* sub, ReconnectOptions& o);
Result<link::RelinkOverrides> relink_overrides(const ReconnectOptions& o);

// "os,mc,intf,appl" (any subset, case-insensitive) -> layer switches.
Result<std::array<bool, 4>> parse_layers(const std::string& text);

// Checks an output path before any drive is talked to: "-" (stdout) passes;
// otherwise not a directory, and its directory exists and is writable.
// `option` names the option in the message ("-o").
Result<void> check_output_path(const std::string& path, const std::string& option);

// "lmcfg backup: <message>" on stderr; returns the exit code for the error
// (SessionHandle::fail while a link is open: with the link advice).
int fail(const char* command, const Error& e);
int exit_code_for(const Error& e);

}  // namespace lmcfg::cli
