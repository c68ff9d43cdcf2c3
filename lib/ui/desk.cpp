// The desk's jobs, drives, plans and files (ui/desk.hpp); what each job does
// is desk_ops.cpp's.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>

#include "common/text.hpp"
#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "ops/backup.hpp"
#include "ops/journal.hpp"
#include "ops/recovery.hpp"
#include "ui/desk_impl.hpp"
#include "ui/upload.hpp"

namespace lmcfg::ui {

namespace fs = std::filesystem;

std::string iso_now() { return ops::utc_now(); }

std::string drive_key(const DriveLink& link) {
  return ops::drive_key(link.port, static_cast<std::uint8_t>(link.id));
}

std::string link_options_text(const DriveLink& l) {
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", l.id & 0xFFu);
  std::string s = "--port " + l.port + " --baud " + std::to_string(l.baud) + " --id " + id;
  if (l.parity != "none") s += " --parity " + l.parity;
  if (l.stop_bits != 1) s += " --stop-bits " + std::to_string(l.stop_bits);
  if (l.checksum != "none") s += " --checksum " + l.checksum;
  if (l.coverage != "id") s += " --checksum-coverage " + l.coverage;
  return s;
}

bool plain_file_name(const std::string& name) {
  if (name.empty() || name == "." || name == ".." || name.size() > 200) return false;
  for (unsigned char c : name)
    if (c < 0x20 || c == '/' || c == '\\' || c == ':' || c == 0x7F) return false;
  return name[0] != '.';
}

namespace {

Json link_json(const DriveLink& l) {
  return Json{{"port", l.port},
              {"baud", l.baud},
              {"parity", l.parity},
              {"stop_bits", l.stop_bits},
              {"checksum", l.checksum},
              {"coverage", l.coverage},
              {"id", l.id}};
}

Json job_json(const DeskJob& j) {
  return Json{{"id", j.id},
              {"kind", j.kind},
              {"drive", j.drive},
              {"port", j.port},
              {"state", j.state},
              {"created", j.created},
              {"finished", j.finished.empty() ? Json(nullptr) : Json(j.finished)},
              {"progress", {{"step", j.step}, {"done", j.done}, {"total", j.total}}},
              {"message", j.message},
              {"exit_code", j.exit_code},
              {"drive_state", j.drive_state},
              {"result", j.result}};
}

// The configuration files of the folder (.json, .xml), newest name first;
// with `key` only the backups of that drive ("<key>-<time>.json").
Json files_of(const fs::path& folder, const std::string& key = "") {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    const std::string ext = it->path().extension().string();
    if (!plain_file_name(n) || (ext != ".json" && ext != ".xml")) continue;
    if (key.empty() || n.rfind(key + "-", 0) == 0) names.push_back(n);
  }
  std::sort(names.rbegin(), names.rend());
  Json out = Json::array();
  for (const auto& n : names) out.push_back(n);
  return out;
}

}  // namespace

std::string Desk::Impl::who() const { return opt.who.empty() ? ops::current_user() : opt.who; }

Result<std::string> Desk::Impl::start(const std::string& kind, const std::string& drive,
                                      const std::string& port,
                                      std::function<void(const std::string&)> work,
                                      const std::string& also) {
  std::lock_guard<std::mutex> lock(mu);
  if (stopping) return Error(Errc::interrupted, "lmcfg ui is stopping: it takes no new work");
  for (const std::string& p : {port, also}) {
    auto b = busy.find(p);
    if (p.empty() || b == busy.end()) continue;
    const DeskJob& other = jobs.at(b->second);
    return Error(Errc::plan_refused, "port " + p + " is busy: " + other.kind + " (job " + other.id +
                                         ", since " + other.created +
                                         ") runs on it; wait until it ends");
  }
  DeskJob j;
  j.id = std::to_string(next_job++);
  j.kind = kind;
  j.drive = drive;
  j.port = port;
  j.created = iso_now();
  const std::string id = j.id;
  jobs[id] = std::move(j);
  order.push_back(id);
  busy[port] = id;
  if (!also.empty()) busy[also] = id;
  threads.emplace_back([this, id, port, also, work = std::move(work)] {
    try {
      work(id);
    } catch (const std::exception& e) {
      fail(id, Error(Errc::io_error, std::string("internal error: ") + e.what()));
    }
    std::lock_guard<std::mutex> l(mu);
    auto& done = jobs.at(id);
    done.state = done.failed ? "failed" : "done";
    done.finished = iso_now();
    for (const std::string& p : {port, also})
      if (busy.count(p) && busy[p] == id) busy.erase(p);
  });
  return id;
}

void Desk::Impl::update(const std::string& id, const std::function<void(DeskJob&)>& f) {
  std::lock_guard<std::mutex> lock(mu);
  f(jobs.at(id));
}

Progress Desk::Impl::progress_of(const std::string& id) {
  return [this, id](const std::string& phase, std::size_t done, std::size_t total) {
    update(id, [&](DeskJob& j) {
      j.step = phase;
      j.done = done;
      j.total = total;
      if (phase == "restore") j.step_done = done > 0 ? done - 1 : 0;
    });
  };
}

void Desk::Impl::fail(const std::string& id, const Error& e) {
  const int code = code_of(e);
  update(id, [&](DeskJob& j) {
    j.failed = true;
    j.message = e.message;
    j.exit_code = code;
  });
}

std::optional<DeskDrive> Desk::Impl::find_drive(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mu);
  auto it = drive_list.find(key);
  if (it == drive_list.end()) return std::nullopt;
  return it->second;
}

void Desk::Impl::remember(const DeskDrive& d) {
  std::lock_guard<std::mutex> lock(mu);
  drive_list[drive_key(d.link)] = d;
}

Result<std::unique_ptr<link::Session>> Desk::Impl::open(const DriveLink& l, bool once) const {
  link::LinkInput in;
  in.port = l.port;
  in.baud = l.baud;
  in.parity = l.parity;
  in.stop_bits = l.stop_bits;
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", l.id & 0xFFu);
  in.id = id;
  in.checksum = l.checksum;
  in.checksum_coverage = l.coverage;
  if (once) in.retries = 0;  // a scan's probes: one each
  in.holder = opt.holder;
  in.cancel = &stopping;
  LMCFG_ASSIGN_OR_RETURN(auto spec, link::make_link_spec(in));
  return link::open_session(spec);
}

Desk::Desk(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Desk::~Desk() {
  stop();
  wait_idle();
}

Result<std::unique_ptr<Desk>> Desk::create(DeskOptions opt) {
  std::error_code ec;
  fs::create_directories(opt.folder, ec);
  if (ec || !fs::is_directory(opt.folder))
    return Error(Errc::file_error, "cannot create the backup folder " + opt.folder.string() + ": " +
                                       (ec ? ec.message() : "not a folder") +
                                       " (choose another with --folder)");
  auto impl = std::make_unique<Impl>(std::move(opt));
  if (!impl->opt.practice_state.empty()) {
    const fs::path dir = impl->opt.folder / "practice";
    const fs::path state = dir / "drive.json";
    fs::create_directories(dir, ec);
    if (!fs::exists(state)) {
      std::ofstream out(state, std::ios::binary);
      out << impl->opt.practice_state;
      if (!out.flush())
        return Error(Errc::file_error, "cannot write the practice drive " + state.string());
    }
    impl->practice = "sim:" + state.string();
  }
  return std::unique_ptr<Desk>(new Desk(std::move(impl)));
}

const fs::path& Desk::folder() const { return impl_->opt.folder; }
std::string Desk::practice_port() const { return impl_->practice; }

Json Desk::ports() const {
  Json list = Json::array();
  for (const auto& p : impl_->opt.list_ports())
    list.push_back({{"port", p.port},
                    {"device", p.device},
                    {"description", p.description},
                    {"vendor_id", p.vendor_id},
                    {"product_id", p.product_id},
                    {"manufacturer", p.manufacturer},
                    {"product", p.product},
                    {"serial", p.serial},
                    {"held_by", p.held_by}});
  return Json{{"ports", list},
              {"practice", impl_->practice.empty() ? Json(nullptr) : Json(impl_->practice)}};
}

Result<std::string> Desk::find(const FindRequest& req) {
  if (req.port.empty())
    return Error(Errc::invalid_argument, "no port given: choose one of the list or type one");
  if (req.first_id > req.last_id || req.last_id > 255)
    return Error(Errc::invalid_argument, "the IDs to scan must be 0..255, from <= to");
  LMCFG_ASSIGN_OR_RETURN(const auto spec, link::parse_port(req.port));
  if (spec.kind() != link::Kind::byte_link)
    return Error(Errc::invalid_argument,
                 "port '" + req.port + "' is a CAN port: lmcfg ui talks LinRS and LinUDP only");
  if (spec.protocol() == link::Protocol::linudp) {
    DriveLink l;
    l.port = req.port;
    return connect(l);
  }
  return impl_->start("find", "", req.port,
                      [this, req](const std::string& id) { impl_->run_find(id, req); });
}

Result<std::string> Desk::connect(const DriveLink& link) {
  LMCFG_ASSIGN_OR_RETURN(const auto spec, link::parse_port(link.port));
  (void)spec;
  return impl_->start("connect", drive_key(link), link.port,
                      [this, link](const std::string& id) { impl_->run_connect(id, link); });
}

namespace {
Error unknown_drive(const std::string& key) {
  return Error(Errc::not_found, "no drive '" + key + "' on this page: find it first");
}
}  // namespace

Result<std::string> Desk::backup(const std::string& drive) {
  auto d = impl_->find_drive(drive);
  if (!d) return unknown_drive(drive);
  return impl_->start("backup", drive, d->link.port,
                      [this, d = *d](const std::string& id) { impl_->run_backup(id, d); });
}

Result<std::string> Desk::compare(const std::string& drive, const std::string& against) {
  auto d = impl_->find_drive(drive);
  if (!d) return unknown_drive(drive);
  std::optional<DeskDrive> other;
  if (against.rfind("drive:", 0) == 0) {
    other = impl_->find_drive(against.substr(6));
    if (!other) return unknown_drive(against.substr(6));
    if (against.substr(6) == drive)
      return Error(Errc::invalid_argument,
                   "a drive compared with itself: choose another drive, a file or factory "
                   "defaults");
  } else if (against != "defaults") {
    LMCFG_TRY(file(against));
  }
  const std::string also =
      other && other->link.port != d->link.port ? other->link.port : std::string();
  return impl_->start(
      "compare", drive, d->link.port,
      [this, d = *d, against, other](const std::string& id) {
        impl_->run_compare(id, d, against, other);
      },
      also);
}

Result<std::string> Desk::plan(const std::string& drive, const std::string& name) {
  auto d = impl_->find_drive(drive);
  if (!d) return unknown_drive(drive);
  LMCFG_ASSIGN_OR_RETURN(const auto path, file(name));
  return impl_->start("plan", drive, d->link.port, [this, d = *d, path](const std::string& id) {
    impl_->run_plan(id, d, path.string(), false);
  });
}

Result<std::string> Desk::plan_undo(const std::string& drive) {
  auto d = impl_->find_drive(drive);
  if (!d) return unknown_drive(drive);
  return impl_->start("plan", drive, d->link.port,
                      [this, d = *d](const std::string& id) { impl_->run_plan(id, d, "", true); });
}

Result<std::string> Desk::execute(const std::string& plan_id, const ops::Audit& audit,
                                  bool skip_incompatible) {
  LMCFG_TRY(check_line("reason", audit.reason, 500));
  LMCFG_TRY(check_line("ticket", audit.ticket, 100));
  if (audit.reason.empty())
    return Error(Errc::invalid_argument, "a reason is required: the journal records why");
  StoredPlan sp;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    auto it = impl_->plans.find(plan_id);
    if (it == impl_->plans.end()) return Error(Errc::not_found, "no plan '" + plan_id + "'");
    if (it->second.expires <= std::chrono::system_clock::now()) {
      impl_->plans.erase(it);
      return Error(Errc::not_found, "plan '" + plan_id + "' expired (a plan is valid for " +
                                        std::to_string(impl_->opt.plan_lifetime.count()) +
                                        " s): make a new one");
    }
    if (!it->second.plan.ok())
      return Error(Errc::plan_refused, "plan '" + plan_id + "' has problems; nothing written");
    if (!it->second.plan.skipped_incompatible.empty() && !skip_incompatible)
      return Error(Errc::plan_refused,
                   "plan '" + plan_id +
                       "' leaves out values this drive cannot take: tick the box to restore "
                       "everything else; nothing written");
    sp = it->second;
  }
  auto d = impl_->find_drive(sp.drive);
  if (!d) return unknown_drive(sp.drive);
  auto id = impl_->start(sp.undo ? "undo" : "restore", sp.drive, d->link.port,
                         [this, sp, audit, skip_incompatible](const std::string& job) {
                           impl_->run_execute(job, sp, audit, skip_incompatible);
                         });
  if (id.ok()) {
    std::lock_guard<std::mutex> lock(impl_->mu);
    impl_->plans.erase(plan_id);  // one use: a new write needs a new plan
  }
  return id;
}

Result<Json> Desk::job(const std::string& id) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->jobs.find(id);
  if (it == impl_->jobs.end()) return Error(Errc::not_found, "no job '" + id + "'");
  return job_json(it->second);
}

Json Desk::jobs() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Json out = Json::array();
  for (auto it = impl_->order.rbegin(); it != impl_->order.rend(); ++it)
    out.push_back(job_json(impl_->jobs.at(*it)));
  return out;
}

Result<std::string> Desk::compare_html(const std::string& id) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->jobs.find(id);
  if (it == impl_->jobs.end() || it->second.kind != "compare")
    return Error(Errc::not_found, "no comparison '" + id + "'");
  if (it->second.html.empty())
    return Error(Errc::not_found, "comparison '" + id + "' has no page (it " +
                                      (it->second.state == "running" ? "runs" : "failed") + ")");
  return it->second.html;
}

Json Desk::drives() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Json out = Json::array();
  for (const auto& [key, d] : impl_->drive_list)
    out.push_back({{"key", key},
                   {"link", link_json(d.link)},
                   {"options", link_options_text(d.link)},
                   {"info", d.info},
                   {"found", d.found}});
  return out;
}

Result<Json> Desk::drive(const std::string& key) const {
  auto d = impl_->find_drive(key);
  if (!d) return unknown_drive(key);
  Json j{{"key", key},
         {"link", link_json(d->link)},
         {"options", link_options_text(d->link)},
         {"info", d->info},
         {"found", d->found},
         {"backups", files_of(impl_->opt.folder, key)},
         {"files", files_of(impl_->opt.folder)}};
  auto path = ops::journal_path();
  auto records = path.ok()
                     ? ops::read_journal(*path, d->link.port, static_cast<std::uint8_t>(d->link.id))
                     : Result<std::vector<nlohmann::ordered_json>>(path.error());
  Json journal = Json::array();
  if (records.ok())
    for (auto it = records->rbegin(); it != records->rend(); ++it) journal.push_back(*it);
  j["journal"] = journal;
  j["journal_error"] = records.ok() ? "" : records.error().message;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    Json others = Json::array();  // the other drives found, to compare with
    for (const auto& [k, other] : impl_->drive_list)
      if (k != key) others.push_back(k);
    j["drives"] = others;
    auto b = impl_->busy.find(d->link.port);
    j["busy_job"] = b == impl_->busy.end() ? Json(nullptr) : Json(b->second);
  }
  return j;
}

Result<fs::path> Desk::file(const std::string& name) const {
  if (!plain_file_name(name))
    return Error(Errc::invalid_argument,
                 "'" + name + "' is not a file name of the backup folder (no folders, no '..')");
  const fs::path p = impl_->opt.folder / name;
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    return Error(Errc::not_found, "no file '" + name + "' in " + impl_->opt.folder.string());
  return p;
}

namespace {

// The name an upload gets in the folder: its own, or "stem-N.ext" past the
// files of that name that hold other bytes; `same` when one holds these.
fs::path upload_target(const fs::path& folder, const std::string& name, std::string_view content,
                       bool& same) {
  const fs::path n(name);
  for (int i = 1; i < 1000; ++i) {
    const fs::path p =
        folder /
        (i == 1 ? name : n.stem().string() + "-" + std::to_string(i) + n.extension().string());
    std::error_code ec;
    if (!fs::exists(p, ec)) return p;
    auto held = config::read_text_file(p);
    if (held.ok() && *held == content) {
      same = true;
      return p;
    }
  }
  return {};
}

}  // namespace

Result<std::string> Desk::store_upload(const std::string& name, std::string_view content) {
  const std::string shown = one_line(name);
  std::string ext = fs::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (name.empty() && content.empty())
    return Error(Errc::invalid_argument,
                 "no file chosen: choose a configuration file (.json or .xml) on this computer");
  if (!valid_utf8(name) || !plain_file_name(name) || (ext != ".json" && ext != ".xml"))
    return Error(Errc::invalid_argument,
                 "'" + shown +
                     "' is not a name lmcfg ui keeps in the backup folder: a file name ending "
                     "in .json or .xml, without folders, ':' or a leading dot; rename the file "
                     "and choose it again");
  if (content.size() > kMaxUpload)
    return Error(Errc::invalid_argument,
                 "'" + shown + "' has " + std::to_string(content.size()) +
                     " bytes, more than lmcfg ui takes (" + std::to_string(kMaxUpload) +
                     " bytes): a drive's configuration file is far smaller; check that this "
                     "is one");
  LMCFG_ASSIGN_OR_RETURN(const auto format, config::format_from_path(name));
  auto cfg = config::read_config_text(content, shown, format);
  if (!cfg.ok())
    return Error(Errc::invalid_argument,
                 "'" + shown + "' is not a configuration file lmcfg reads (" + cfg.error().message +
                     "); choose a file that lmcfg backup or this page wrote (JSON or XML)");
  bool same = false;
  const fs::path to = upload_target(impl_->opt.folder, name, content, same);
  if (to.empty())
    return Error(Errc::invalid_argument, "the backup folder holds 999 files named like '" + shown +
                                             "': rename the file and choose it again");
  if (!same) LMCFG_TRY(config::write_file_atomic(to, content));
  return to.filename().string();
}

bool Desk::busy() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return !impl_->busy.empty();
}

void Desk::stop() { impl_->stopping = true; }

void Desk::wait_idle() {
  for (;;) {
    std::vector<std::thread> ts;
    {
      std::lock_guard<std::mutex> lock(impl_->mu);
      ts.swap(impl_->threads);
    }
    if (ts.empty()) return;
    for (auto& t : ts) t.join();
  }
}

}  // namespace lmcfg::ui
