#pragma once
// The service's threads against its control group's task limit (systemd's
// TasksMax=, the cgroup's pids.max). A thread the kernel refuses at start
// would end the service with an exception; one refused later would leave a
// line without its worker. So the start compares the two and refuses, saying
// what to raise, when the inventory needs more than the limit allows.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/result.hpp"
#include "fleet/inventory.hpp"

namespace lmcfg::serve {

// The tasks lmcfg serve runs for `inv` with `http_workers` HTTP workers: the
// main thread (the schedule), the HTTP event loop and its workers, the
// notifier and the notify command it runs, the archive push, one worker per
// line.
std::size_t tasks_needed(const fleet::Inventory& inv, int http_workers);

// The pids.max file of this process's control group, from the text of
// /proc/self/cgroup (cgroup v2 "0::/path", or v1's "N:pids:/path");
// "" when it names none.
std::string pids_max_path(std::string_view proc_self_cgroup);
// The limit in a pids.max file's text: a number, or nullopt for "max".
std::optional<std::uint64_t> parse_pids_max(std::string_view text);
// This process's limit and the file it came from; nullopt where there is
// none (no cgroup, no pids controller, "max", Windows).
struct TaskLimit {
  std::uint64_t limit = 0;
  std::string file;
};
std::optional<TaskLimit> own_task_limit();

// Errc::invalid_argument when `needed` tasks do not fit in `limit`, saying
// both, why, and the TasksMax= to set.
Result<void> check_task_limit(const fleet::Inventory& inv, int http_workers,
                              const std::optional<TaskLimit>& limit);

}  // namespace lmcfg::serve
