// What the service tells about itself: Prometheus /metrics, the daily summary
// event, and the events of [archive] push (its thread: archive_push.cpp).
#include <algorithm>
#include <cstdio>

#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace {

// Prometheus label value: backslash, double quote and newline escaped.
std::string label(std::string_view v) {
  std::string s;
  for (char c : v) {
    if (c == '\\' || c == '"') s += '\\';
    if (c == '\n') {
      s += "\\n";
      continue;
    }
    s += c;
  }
  return s;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Positions per status (the summary event and /metrics, one list): ok, drift,
// failed, replaced, unknown.
Json status_counts(const fleet::Inventory& inventory,
                   const std::map<std::string, DriveState>& states) {
  Json counts{{"ok", 0}, {"drift", 0}, {"failed", 0}, {"replaced", 0}, {"unknown", 0}};
  for (const auto& line : inventory.lines) {
    for (const auto& d : line.drives) {
      auto it = states.find(d.name);
      const std::string st = it == states.end() ? "unknown" : it->second.status;
      counts[st] = counts.value(st, 0) + 1;
    }
  }
  return counts;
}

}  // namespace

// An event about the archive, not a position: push_failed, push_recovered.
void Service::Impl::emit_archive(const std::string& event, Json details) {
  Json j{{"event", event}, {"remote", opt.inventory.archive.push}, {"time", iso_time(opt.clock())}};
  for (auto& [k, v] : details.items()) j[k] = v;
  log("event " + event + ": push to " + opt.inventory.archive.push);
  notify(j);
}

void Service::summarize(TimePoint now) {
  auto& s = *impl_;
  const std::int64_t day =
      std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count() / 86400;
  Json counts;
  {
    std::lock_guard<std::mutex> lock(s.mu);
    if (!s.summary_day) {
      s.summary_day = day;  // the first day is summarized when it ends
      return;
    }
    if (day <= *s.summary_day) return;
    s.summary_day = day;
  }
  counts = s.store.read(
      [&](const StateStore::Data& data) { return status_counts(s.opt.inventory, data.states); });
  s.emit("summary", "", "",
         {{"period", "day"}, {"drives", s.opt.inventory.drive_count()}, {"counts", counts}});
}

std::string Service::metrics() const {
  const auto& s = *impl_;
  // Each part's numbers copied under its own lock, then written out with none.
  const auto states = s.store.read([](const StateStore::Data& data) { return data.states; });
  const auto line_metrics = s.lines.metrics();
  std::string o;
  auto head = [&](const char* name, const char* type, const char* help) {
    o += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  };
  head("lmcfg_serve_uptime_seconds", "gauge", "Seconds since the service started.");
  o += "lmcfg_serve_uptime_seconds " +
       number(std::chrono::duration<double>(s.opt.clock() - s.started).count()) + "\n";
  auto per_drive = [&](const char* name, const char* type, const char* help, auto value) {
    head(name, type, help);
    for (const auto& line : s.opt.inventory.lines) {
      for (const auto& d : line.drives) {
        auto it = states.find(d.name);
        static const DriveState kUnknown;
        const DriveState& st = it == states.end() ? kUnknown : it->second;
        auto v = value(st);
        if (!v) continue;
        o += std::string(name) + "{drive=\"" + label(d.name) + "\",line=\"" + label(line.name) +
             "\"} " + number(*v) + "\n";
      }
    }
  };
  per_drive("lmcfg_drive_last_backup_timestamp_seconds", "gauge",
            "Time of the drive's last successful backup (Unix time).",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_backup) return std::nullopt;
              return epoch_seconds(*st.last_backup);
            });
  per_drive("lmcfg_drive_last_attempt_success", "gauge",
            "1 when the last read of the drive (backup or drift check) succeeded, else 0.",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_attempt) return std::nullopt;
              return st.last_ok ? 1 : 0;
            });
  per_drive("lmcfg_drive_last_attempt_exit_code", "gauge",
            "The CLI exit code of the last attempt's result (0 ok, 4 link, 5 drive refused).",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_attempt) return std::nullopt;
              return st.last_exit_code;
            });
  per_drive(
      "lmcfg_drive_drift", "gauge", "1 when the drive differs from its approved configuration.",
      [](const DriveState& st) -> std::optional<double> { return st.status == "drift" ? 1 : 0; });
  per_drive("lmcfg_drive_differences", "gauge",
            "Differences between the drive and its approved configuration at the last check.",
            [](const DriveState& st) -> std::optional<double> {
              return static_cast<double>(st.differences);
            });
  per_drive("lmcfg_drive_restore_retries_failed_total", "counter",
            "Automatic retries of a failed restore of the drive that failed again.",
            [](const DriveState& st) -> std::optional<double> {
              return static_cast<double>(st.retries_failed);
            });
  head("lmcfg_drives", "gauge", "Positions per status against their approved configuration.");
  const Json counts = status_counts(s.opt.inventory, states);  // named: items() refers to it
  for (const auto& [status, n] : counts.items())
    o += "lmcfg_drives{status=\"" + status + "\"} " + number(n.get<double>()) + "\n";
  auto per_line = [&](const char* name, const char* type, const char* help, auto value) {
    head(name, type, help);
    for (std::size_t l = 0; l < s.opt.inventory.lines.size(); ++l)
      o += std::string(name) + "{line=\"" + label(s.opt.inventory.lines[l].name) + "\"} " +
           number(value(line_metrics[l])) + "\n";
  };
  per_line("lmcfg_line_telegrams_total", "counter", "Telegrams sent on the line.",
           [](const LineMetrics& m) { return static_cast<double>(m.telegrams); });
  per_line("lmcfg_line_retries_total", "counter", "Telegrams repeated after a lost or bad answer.",
           [](const LineMetrics& m) { return static_cast<double>(m.retries); });
  per_line("lmcfg_line_timeouts_total", "counter", "Answers not received in time.",
           [](const LineMetrics& m) { return static_cast<double>(m.timeouts); });
  per_line("lmcfg_line_errors_total", "counter", "Drive reads on the line that failed.",
           [](const LineMetrics& m) { return static_cast<double>(m.errors); });
  per_line("lmcfg_line_runs_total", "counter", "Jobs run on the line.",
           [](const LineMetrics& m) { return static_cast<double>(m.runs); });
  per_line("lmcfg_line_run_seconds_total", "counter", "Seconds the line's jobs took in total.",
           [](const LineMetrics& m) { return m.run_seconds; });
  per_line("lmcfg_line_last_run_seconds", "gauge", "Seconds the line's last job took.",
           [](const LineMetrics& m) { return m.last_run_seconds; });
  if (!s.pusher) return o;
  const Pusher::Stats push = s.pusher->stats();
  head("lmcfg_archive_push_pending", "gauge",
       "1 while a commit of the archive is not pushed to [archive] push yet, else 0.");
  o += "lmcfg_archive_push_pending " + number(push.pending ? 1 : 0) + "\n";
  head("lmcfg_archive_push_failures_total", "counter", "Pushes of the archive that failed.");
  o += "lmcfg_archive_push_failures_total " + number(static_cast<double>(push.failures)) + "\n";
  head("lmcfg_archive_push_last_success_timestamp_seconds", "gauge",
       "Time of the last successful push of the archive (Unix time).");
  if (push.last_success)
    o += "lmcfg_archive_push_last_success_timestamp_seconds " +
         number(epoch_seconds(*push.last_success)) + "\n";
  return o;
}

}  // namespace lmcfg::serve
