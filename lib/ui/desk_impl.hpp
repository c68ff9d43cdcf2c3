#pragma once
// The desk's private parts, shared by desk.cpp (jobs, drives, files) and
// desk_ops.cpp (what each job does on its thread).
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "config/model.hpp"
#include "link/session.hpp"
#include "ops/restore.hpp"
#include "ui/desk.hpp"

namespace lmcfg::ui {

using TimePoint = std::chrono::system_clock::time_point;

struct DeskJob {
  std::string id, kind, drive, port;
  std::string state = "running";
  std::string created, finished;
  std::string step;
  std::size_t done = 0, total = 0;
  std::size_t step_done = 0;  // restore: steps finished before the one in hand
  // Failed, said as the job's state only when it has ended and its ports are
  // free: a page that sees "failed" may start the way out at once.
  bool failed = false;
  std::string message;  // the CLI's message of a failure
  int exit_code = 0;
  std::string drive_state;  // a failed write: what the drive holds now
  Json result = Json::object();
  std::string html;  // compare: the diff page
};

struct DeskDrive {
  DriveLink link;
  Json info;          // the last state read (ops::render_info_json), null before
  std::string found;  // how it was found ("answered", "connected")
};

struct StoredPlan {
  std::string id, drive, file_name;
  bool undo = false;
  config::DriveConfig file;
  ops::Plan plan;
  TimePoint expires;
};

struct Desk::Impl {
  DeskOptions opt;
  mutable std::mutex mu;
  std::map<std::string, DeskJob> jobs;
  std::vector<std::string> order;               // job ids, oldest first
  std::map<std::string, std::string> busy;      // port -> job id
  std::map<std::string, DeskDrive> drive_list;  // key -> drive
  std::map<std::string, StoredPlan> plans;
  std::vector<std::thread> threads;
  std::atomic<bool> stopping{false};
  int next_job = 1, next_plan = 1;
  std::string practice;  // the practice drive's port

  explicit Impl(DeskOptions o) : opt(std::move(o)) {}

  // Starts `work` on a thread of its own as job `kind` on `port` (and
  // `also`, a second port it uses: a comparison of two drives);
  // Errc::plan_refused when a port is busy.
  Result<std::string> start(const std::string& kind, const std::string& drive,
                            const std::string& port, std::function<void(const std::string&)> work,
                            const std::string& also = "");
  // Updates a job under the lock.
  void update(const std::string& id, const std::function<void(DeskJob&)>& f);
  Progress progress_of(const std::string& id);
  std::optional<DeskDrive> find_drive(const std::string& key) const;
  void remember(const DeskDrive& d);
  Result<std::unique_ptr<link::Session>> open(const DriveLink& l, bool once = false) const;
  int code_of(const Error& e) const { return opt.exit_code ? opt.exit_code(e) : 70; }
  std::string who() const;

  // The jobs' work (desk_ops.cpp), each on its own thread.
  void run_find(const std::string& job, const FindRequest& req);
  void run_connect(const std::string& job, const DriveLink& link);
  void run_backup(const std::string& job, const DeskDrive& d);
  void run_compare(const std::string& job, const DeskDrive& d, const std::string& against,
                   const std::optional<DeskDrive>& other);
  // The configuration `against` names for a comparison: a file of the
  // folder, or another drive read now; unset for factory defaults.
  Result<std::optional<config::DriveConfig>> compare_side(const std::string& job,
                                                          const std::string& against,
                                                          const std::optional<DeskDrive>& other);
  void run_plan(const std::string& job, const DeskDrive& d, const std::string& file, bool undo);
  void run_execute(const std::string& job, const StoredPlan& sp, const ops::Audit& audit,
                   bool skip);
  void fail(const std::string& id, const Error& e);
};

std::string iso_now();

}  // namespace lmcfg::ui
