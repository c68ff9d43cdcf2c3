#pragma once
// The technician's desk behind `lmcfg ui` (docs/ui.md): the drives found on
// this computer's ports, one drive at a time, and the operations on them:
// find, read its state, back up into a folder, compare, plan a restore of a
// file or of the last undo record, write it. Each operation is a job on a
// thread of its own (never the HTTP worker's), through the same library calls
// as the CLI: the port's lock (holder "lmcfg ui"), the recovery record and the
// undo record in the CLI's state folder, the journal. So a restore the page
// left unfinished is finished by `lmcfg restore` and the other way round.
//
// One operation per port at a time: a second one on a busy port is refused
// with what runs there. Jobs outlive the page that started them: closing the
// tab stops nothing, the job page shows the progress again when reopened.
// This class knows no HTTP (ui/server.hpp turns requests into these calls).
#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "db/database.hpp"
#include "ops/audit.hpp"
#include "ui/ports.hpp"

namespace lmcfg::ui {

using Json = nlohmann::ordered_json;

struct DeskOptions {
  std::filesystem::path folder;  // where backups go (created when missing)
  std::reference_wrapper<const db::Database> db = db::Database::empty();
  // The practice drive's simulator state (docs/simulator.md): written once to
  // <folder>/practice/drive.json and offered as its sim: port; "" = none.
  std::string practice_state;
  // The CLI's exit code of an error and its category (docs/cli.md "Exit
  // codes"), for the journal and the pages.
  std::function<int(const Error&)> exit_code;
  std::function<std::string(int)> exit_category;
  std::string holder = "lmcfg ui";  // in the port's lock while a job uses it
  std::string who;                  // the journal's operator ("" = ops::current_user())
  std::chrono::seconds plan_lifetime{600};
  std::function<std::vector<SerialPortInfo>()> list_ports = [] { return ui::list_ports(); };
};

// How to reach one drive: what `--port --baud ... --id` would say.
struct DriveLink {
  std::string port;
  unsigned baud = 57600;
  std::string parity = "none";
  unsigned stop_bits = 1;
  std::string checksum = "none";
  std::string coverage = "id";
  unsigned id = 0x11;
};

// What a find scans (a LinRS line); the defaults are `lmcfg scan`'s.
struct FindRequest {
  std::string port;
  std::vector<unsigned> bauds;  // empty: every rate, factory 57600 first
  unsigned first_id = 0, last_id = 255;
};

class Desk {
 public:
  static Result<std::unique_ptr<Desk>> create(DeskOptions opt);
  ~Desk();  // stop() and wait for the jobs
  Desk(const Desk&) = delete;
  Desk& operator=(const Desk&) = delete;

  const std::filesystem::path& folder() const;
  // The practice drive's port ("sim:<folder>/practice/drive.json"), "" without one.
  std::string practice_port() const;
  // The connect page: {"ports":[{port, device, description, vendor_id, product_id,
  // manufacturer, product, serial, held_by}], "practice": port or null}.
  Json ports() const;

  // Jobs; each returns the job's id. A port in use by another job of this
  // desk: Errc::plan_refused saying what runs there. An unknown drive or
  // file: Errc::not_found; bad input: Errc::invalid_argument.
  Result<std::string> find(const FindRequest& req);
  // A drive at known link settings (a LinUDP address, a drive found before).
  Result<std::string> connect(const DriveLink& link);
  Result<std::string> backup(const std::string& drive);
  // `against`: "defaults", the name of a file in the folder or "drive:KEY",
  // another drive found (both ports are taken while it runs).
  Result<std::string> compare(const std::string& drive, const std::string& against);
  // The plan of restoring `file` (a name in the folder) onto the drive; the
  // job's result has the plan's id.
  Result<std::string> plan(const std::string& drive, const std::string& file);
  // The plan of putting the drive's newest undo record back (lmcfg undo).
  Result<std::string> plan_undo(const std::string& drive);
  // Writes a plan this desk made: re-reads the drive and refuses when it
  // changed since; undo record, recovery record and journal as the CLI.
  Result<std::string> execute(const std::string& plan_id, const ops::Audit& audit,
                              bool skip_incompatible);

  // {"id","kind","drive","port","state" ("running"|"done"|"failed"),"created","finished",
  //  "progress":{"step","done","total"},"message","exit_code","drive_state","result":{...}}
  Result<Json> job(const std::string& id) const;
  // Every job, newest first (the connect page lists those running).
  Json jobs() const;
  // A compare job's page (report::render_diff_report).
  Result<std::string> compare_html(const std::string& job_id) const;
  // A plan as the console's plan parts read it (serve/console_pages.hpp):
  // {"plan_id","drive","port","id","file","undo","expires","nothing_to_do","steps",
  //  "losses","notes","problems","incompatible","factory_fresh"}.
  Result<Json> plan_json(const std::string& plan_id) const;

  // Drives found or connected: [{"key","link":{...},"options","info","found"}].
  Json drives() const;
  // One drive: its backups in the folder ("backups", newest first), every
  // configuration file of the folder ("files") and its journal.
  Result<Json> drive(const std::string& key) const;
  // `lmcfg report FILE` of a file of the folder: the HTML page (reads the
  // file only, no drive).
  Result<std::string> report_html(const std::string& name) const;
  // An uploaded file into the folder: `name` as the browser gave it (a
  // plain file name ending in .json or .xml), `content` at most kMaxUpload
  // bytes (ui/upload.hpp) and read as a configuration file. Kept under its
  // own name, or NAME-2.json, NAME-3.json ... when the folder holds another
  // file of that name (the same bytes: that file). The name in the folder;
  // Errc::invalid_argument saying what is wrong, nothing written.
  Result<std::string> store_upload(const std::string& name, std::string_view content);
  // A file of the folder by its name (no path parts): for downloads.
  Result<std::filesystem::path> file(const std::string& name) const;
  // Whether a job runs now (Quit waits for none: the page asks first).
  bool busy() const;
  // No new jobs; a running job stops between two telegrams (the CLI's
  // Ctrl-C): a restore leaves its recovery record for the next run.
  void stop();
  void wait_idle();

  struct Impl;

 private:
  explicit Desk(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// "sim:/x/drive.json" and MACID 11h: "sim__x_drive.json-11h" (ops::drive_key).
std::string drive_key(const DriveLink& link);
// "--port P --baud 57600 --id 0x11" (+ --parity/--stop-bits/--checksum when
// not the defaults): the CLI's options for the same drive.
std::string link_options_text(const DriveLink& link);
// Whether `name` may be a file of the folder: one path part, no "..".
bool plain_file_name(const std::string& name);

}  // namespace lmcfg::ui
