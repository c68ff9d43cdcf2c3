#pragma once
// lmcfg serve (docs/serve.md): the plant service over a fleet inventory and
// its archive. Scheduled backups (commit only on change) and drift checks,
// one worker per line (a line's drives in sequence, through lib/fleet's
// read_line/compare_line/write_line, the same functions as `fleet backup` and
// `fleet status`), a state per position with notifications on changes only,
// the numbers /metrics shows and the answers of the REST API.
//
// The clock is the caller's: tick(now) queues the jobs due at `now`, so tests
// drive the schedule without sleeping. The HTTP server (serve/http.hpp) is a
// thin adapter over the public calls here.
#include <chrono>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>

#include "common/result.hpp"
#include "db/database.hpp"
#include "fleet/fleet.hpp"
#include "fleet/inventory.hpp"
#include "link/session.hpp"
#include "ops/audit.hpp"
#include "ops/backup.hpp"

namespace lmcfg::serve {

using Clock = std::chrono::system_clock;
using TimePoint = Clock::time_point;
using Json = nlohmann::ordered_json;

struct ServiceOptions {
  fleet::Inventory inventory;
  std::string archive;               // the archive's directory (created when new or empty)
  std::vector<ops::LineLink> links;  // one per inventory line, same order (LinRS or DeviceNet)
  std::reference_wrapper<const db::Database> db = db::Database::empty();
  ops::BackupOptions backup;  // what to read
  // The CLI's exit code for an error (README "Exit codes"): events and API
  // errors carry it as their category.
  std::function<int(const Error&)> exit_code;
  std::function<void(const std::string&)> log;                     // one line per event, no newline
  std::function<void(const Json&)> notify;                         // each state change (event JSON)
  std::function<TimePoint()> clock = [] { return Clock::now(); };  // times in states and events
  // [archive] push: after a failed push the next try waits push_retry_first,
  // then twice as long each time, at most push_retry_max (real time, on the
  // push thread; backups and commits go on meanwhile).
  std::chrono::milliseconds push_retry_first{1000};
  std::chrono::milliseconds push_retry_max{std::chrono::minutes(5)};
  // Where the service keeps what must outlive it (docs/serve.md "State"): the
  // restores in progress (resumed at the next start), the drives' recovery and
  // undo records. "" = <archive>/.git/lmcfg-serve.
  std::string state_dir;
  // The archive's commits are by "lmcfg serve on HOST" (the person who asked
  // is in the message's Operator trailer); "" = this computer's name.
  std::string host;
  // How long a plan may wait for its execution.
  std::chrono::seconds plan_lifetime{300};
  // Live reads (a diff to=live, a plan) run on the line's worker as jobs; the
  // request waits for one at most live_wait, and only while fewer than
  // live_waiters other requests wait (the HTTP server's other workers stay
  // free); otherwise the answer is line_busy (HTTP 503, Retry-After).
  std::chrono::milliseconds live_wait{1500};
  std::size_t live_waiters = 2;
  // Live reads queued on one line at most; more are refused as line_busy.
  std::size_t live_queued = 8;
};

// A live read that did not end while its request waited (the line is busy
// with other work, or the drive is slow to answer): its job (empty when the
// line had too many queued to take another), how long to wait before asking
// again. The same request asked again gets the job's answer once it has
// ended; GET /api/v1/jobs/{job} shows it too.
struct LineBusy {
  std::string job;
  int retry_after_s = 2;
};
// The error code of line_busy: its value is the job's number (0: none).
const std::error_category& line_busy_category() noexcept;
std::optional<LineBusy> line_busy(const Error& e);

// "2026-11-24T17:20:15Z"
std::string iso_time(TimePoint t);

class Service {
 public:
  static Result<std::unique_ptr<Service>> create(ServiceOptions opt);
  ~Service();  // stop() and wait for the workers
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  // Queues the scheduled jobs due at `now` on the lines' workers; the first
  // tick runs both (a backup, then a drift check), later ones every
  // backup_every / status_every after the previous due time.
  void tick(TimePoint now);
  // When a job kind is next due; nullopt when the inventory schedules none.
  std::optional<TimePoint> next_backup() const;
  std::optional<TimePoint> next_status() const;

  // Free text (who, reason, ticket, revisions) is checked first (common/text.hpp
  // check_line): one line of UTF-8 without control characters, at most
  // kMaxWhoBytes / kMaxReasonBytes / kMaxTicketBytes / kMaxRevBytes bytes;
  // Errc::invalid_argument naming the field otherwise. Revisions are resolved to
  // commit ids before they reach a commit message, a job record or a page.
  //
  // API: Errc::not_found for a name not in the inventory. The job's id.
  // `who` asked for it: the backup's commit carries it as its Operator trailer
  // ("" = a scheduled run, no trailer).
  Result<std::string> backup_drive(const std::string& name, const std::string& who = "");
  Result<std::string> backup_line(const std::string& line, const std::string& who = "");
  // {"id","kind" ("backup"|"restore"),"scope","state" ("queued"|"running"|"done"|"failed"),
  //  "created","finished","progress":{"done","total","step"},"outcome","message","commit",
  //  ...; backups also "drives","done","counts","commits","errors"}
  Result<Json> job(const std::string& id) const;

  // Plans restoring `name`'s archived file at `rev` ("" = the archive's HEAD) onto the drive now at
  // that position, reading the target on the line's worker (waits for it at most
  // ServiceOptions::live_wait; then the line_busy error, and the same plan asked
  // again, by the same `who`, gets the job's answer once it has ended). Json:
  // {"plan_id","drive","line","rev","commit","expires" (ISO
  // time),"steps":[{"kind","upid","name","old","new","unit",...}],
  //  "problems":[{"kind","message",...}],"incompatible":[...],"factory_fresh":bool}
  Result<Json> plan(const std::string& name, const std::string& rev, const std::string& who);
  struct ExecuteRequest {
    std::string plan_id;
    ops::Audit audit;
    bool skip_incompatible = false;
  };
  // Queues the plan's execution on the line's worker; the job id. Errc for an unknown or expired
  // plan (say which), a missing reason under require_reason, problems without skip_incompatible.
  // At execution the target is re-read and compared with what the plan saw; a change refuses.
  Result<std::string> execute(const ExecuteRequest& req);
  // The diff of `name`'s archived file at `from` and `to` (revisions; `to` may be "live": the
  // drive read on the line's worker, waited for as plan() does), as `lmcfg diff --json` writes
  // it, the position's ignored UPIDs left out.
  Result<Json> diff(const std::string& name, const std::string& from, const std::string& to) const;
  // The same diff as `lmcfg report A B` renders it (the console's diff pages).
  Result<std::string> diff_html(const std::string& name, const std::string& from,
                                const std::string& to) const;
  // `lmcfg report` of `name`'s archived file at `rev` ("" = HEAD): the HTML page.
  Result<std::string> report_html(const std::string& name, const std::string& rev) const;

  struct ApproveRequest {
    std::string rev;  // "" = HEAD; resolved to its commit id before it is recorded
    std::string who, reason, ticket;
  };
  // Records `name`'s file at req.rev as the position's approved configuration
  // (fleet/approved.hpp) and queues a drift check of the position against it.
  // {rev, time, who, reason, ticket, kind, job}. Errc::invalid_argument without a
  // reason, Errc::not_found for an unknown drive, revision or a revision
  // without the position's file; nothing recorded then.
  Result<Json> approve(const std::string& name, const ApproveRequest& req);

  // Cancels the automatic retry of a failed restore that waits for `name`'s
  // drive (the position's "retry" in drive()): the restore is not run again and
  // the drive stays as the failure left it (its "drive_state"), which the
  // position then says. `who` cancels it (recorded in the log and the event).
  // {drive, cancelled_job, drive_state}. Errc::not_found for an unknown drive or
  // no retry waiting; Errc::plan_refused (HTTP 409) while the retry runs (a
  // restore is not stopped between its writes).
  Result<Json> cancel_retry(const std::string& name, const std::string& who);

  // Sends the daily summary event when a day (UTC) has begun since the last one: counts of
  // positions per status. tick() calls it; tests call it with their clock.
  void summarize(TimePoint now);
  // Every position's state, in the inventory's order (GET /api/v1/drives).
  Json drives() const;
  // The same as the text of drives().dump(2), written without building the
  // array: at thousands of positions the objects were most of the time.
  std::string drives_text() const;
  // Each position's name, line, id, status and last_backup only, as in
  // drives(): what the overview counts and filters by.
  Json drive_summaries() const;
  Result<Json> drive(const std::string& name) const;
  Result<Json> history(const std::string& name) const;
  // The inventory served (positions, labels), for the console's pages.
  const fleet::Inventory& inventory() const;
  // Prometheus text exposition format (version 0.0.4).
  std::string metrics() const;
  // The address people reach the service at ("http://127.0.0.1:8470"), known
  // once the HTTP server is bound: drift events link to the console's diff
  // page under it. Until set, the links are paths ("/diff?...").
  void set_base_url(const std::string& url);

  // Until every queued job has finished.
  void wait_idle();
  // No new jobs; each worker finishes the drive in hand (with links whose
  // client.cancel is set, the telegram in flight) and stops.
  void stop();

  struct Impl;

 private:
  explicit Service(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::serve
