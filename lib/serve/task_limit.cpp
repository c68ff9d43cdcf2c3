#include "serve/task_limit.hpp"

#include <algorithm>

#include "config/atomic_file.hpp"

namespace lmcfg::serve {

std::size_t tasks_needed(const fleet::Inventory& inv, int http_workers) {
  const std::size_t fixed = 1 /* main: the schedule */ + 1 /* HTTP event loop */ +
                            1 /* notifier */ + 1 /* its notify command */ + 1 /* archive push */;
  return fixed + static_cast<std::size_t>(std::max(1, http_workers)) + inv.lines.size();
}

std::string pids_max_path(std::string_view proc_self_cgroup) {
  std::string v2;
  std::size_t at = 0;
  while (at < proc_self_cgroup.size()) {
    std::size_t end = proc_self_cgroup.find('\n', at);
    if (end == std::string_view::npos) end = proc_self_cgroup.size();
    const std::string_view line = proc_self_cgroup.substr(at, end - at);
    at = end + 1;
    // hierarchy-ID:controller-list:path (cgroups(7))
    const std::size_t c1 = line.find(':');
    const std::size_t c2 = c1 == std::string_view::npos ? c1 : line.find(':', c1 + 1);
    if (c2 == std::string_view::npos) continue;
    const std::string_view id = line.substr(0, c1), controllers = line.substr(c1 + 1, c2 - c1 - 1);
    const std::string path(line.substr(c2 + 1));
    if (id == "0" && controllers.empty()) {
      v2 = "/sys/fs/cgroup" + (path == "/" ? std::string() : path) + "/pids.max";
      continue;
    }
    // v1: the pids controller, alone or among others ("pids" or "cpu,pids").
    std::size_t p = 0;
    while (p <= controllers.size()) {
      std::size_t q = controllers.find(',', p);
      if (q == std::string_view::npos) q = controllers.size();
      if (controllers.substr(p, q - p) == "pids")
        return "/sys/fs/cgroup/pids" + (path == "/" ? std::string() : path) + "/pids.max";
      p = q + 1;
    }
  }
  return v2;
}

std::optional<std::uint64_t> parse_pids_max(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != text.npos)
    return std::nullopt;  // "max", or not a limit we can read
  return std::stoull(std::string(text));
}

std::optional<TaskLimit> own_task_limit() {
  // Both are pseudo-files of a few bytes, read as streams.
  constexpr std::size_t kMax = 64 * 1024;
  const auto cgroup = config::read_text_file("/proc/self/cgroup", kMax);
  if (!cgroup.ok()) return std::nullopt;
  const std::string file = pids_max_path(*cgroup);
  if (file.empty()) return std::nullopt;
  const auto text = config::read_text_file(file, kMax);
  if (!text.ok()) return std::nullopt;
  const auto limit = parse_pids_max(*text);
  if (!limit) return std::nullopt;
  return TaskLimit{*limit, file};
}

Result<void> check_task_limit(const fleet::Inventory& inv, int http_workers,
                              const std::optional<TaskLimit>& limit) {
  if (!limit) return {};
  const std::size_t needed = tasks_needed(inv, http_workers);
  if (needed <= limit->limit) return {};
  // Room for a tenth more lines, so that the next line added does not stop it again.
  const std::size_t suggest = needed + std::max<std::size_t>(8, inv.lines.size() / 10);
  return Error(Errc::invalid_argument,
               "the inventory's " + std::to_string(inv.lines.size()) + " line(s) need " +
                   std::to_string(needed) + " tasks (a worker per line, " +
                   std::to_string(std::max(1, http_workers)) +
                   " HTTP workers, the event loop, the schedule, the notifier and its command, "
                   "the archive push), and this control group allows " +
                   std::to_string(limit->limit) + " (" + limit->file +
                   ", systemd's TasksMax=): raise it with `systemctl edit lmcfg-serve`, "
                   "[Service] TasksMax=" +
                   std::to_string(suggest) + ", or split the inventory");
}

}  // namespace lmcfg::serve
