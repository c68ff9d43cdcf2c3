#include "common/executable.hpp"

namespace lmcfg {

Result<std::filesystem::path> running_executable() {
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec)
    return Error(Errc::file_error,
                 "cannot locate the running executable via /proc/self/exe (" + ec.message() + ")");
  return exe;
}

}  // namespace lmcfg
