// One program per port: flock(2) on the serial device plus a small file that
// says who holds it. Terminal programs (minicom, picocom) take a lock too, so
// that two of them never talk on one line at the same time; here two LinRS
// masters on one RS485 line would collide on the wire and each would take the
// other's answers for its own.
#include "transport/port_lock.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace lmcfg::transport {

namespace {

std::string canonical_device(const std::string& device) {
  std::error_code ec;
  auto real = std::filesystem::canonical(device, ec);  // /dev/serial/by-id/... -> /dev/ttyUSB0
  return ec ? device : real.string();
}

// "/dev/ttyUSB0" -> "%2Fdev%2FttyUSB0.holder": one file per device, its name
// the canonical path with '/' and '%' escaped (no two paths share a name).
std::string info_file_name(const std::string& device) {
  std::string name;
  for (char c : canonical_device(device)) {
    if (c == '/')
      name += "%2F";
    else if (c == '%')
      name += "%25";
    else
      name += c;
  }
  return name + ".holder";
}

bool alive(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

std::optional<PortHolder> read_info(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  PortHolder h;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("pid=", 0) == 0) h.pid = std::strtol(line.c_str() + 4, nullptr, 10);
    if (line.rfind("holder=", 0) == 0) h.holder = line.substr(7);
  }
  if (!alive(h.pid)) return std::nullopt;  // a stale file of a program that died
  return h;
}

// Creates `dir` so that every user may put files in it (sticky, like /tmp):
// the holder of a port may be another user than the one asking.
bool usable_dir(const std::string& dir) {
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    if (::mkdir(dir.c_str(), 01777) != 0 && errno != EEXIST) return false;
    ::chmod(dir.c_str(), 01777);  // mkdir's mode went through the umask
  }
  return ::access(dir.c_str(), W_OK | X_OK) == 0;
}

}  // namespace

std::vector<std::string> port_lock_dirs() {
  std::vector<std::string> dirs{"/run/lock/lmcfg"};
  if (const char* x = std::getenv("XDG_RUNTIME_DIR"); x && *x)
    dirs.push_back(std::string(x) + "/lmcfg");
  dirs.push_back("/tmp/lmcfg-lock");
  return dirs;
}

std::optional<PortHolder> port_holder(const std::string& device) {
  const std::string name = info_file_name(device);
  for (const auto& dir : port_lock_dirs())
    if (auto h = read_info(dir + "/" + name)) return h;
  return std::nullopt;
}

std::string port_in_use_message(const std::string& device) {
  return in_use_text(device, port_holder(device));
}

PortLock::~PortLock() {
  if (info_path_.empty()) return;
  // Only our own record: a newer holder may have replaced a file we left.
  if (auto h = read_info(info_path_); h && h->pid == static_cast<long>(::getpid()))
    ::unlink(info_path_.c_str());
}

Result<std::unique_ptr<PortLock>> PortLock::take(int fd, const std::string& device,
                                                 const PortClaim& claim) {
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK)
      return Error(Errc::io_error,
                   "cannot lock serial port " + device + ": flock: " + std::strerror(errno));
    // The holder writes its record right after taking the lock: give it a moment.
    for (int i = 0; i < 10 && !port_holder(device); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return Error(Errc::io_error, port_in_use_message(device));
  }
  auto lock = std::unique_ptr<PortLock>(new PortLock);
  if (claim.holder.empty()) return lock;
  const std::string name = info_file_name(device);
  const std::string pid = std::to_string(::getpid());
  for (const auto& dir : port_lock_dirs()) {
    if (!usable_dir(dir)) continue;
    const std::string path = dir + "/" + name;
    const std::string tmp = path + "." + pid + ".tmp";
    {
      std::ofstream out(tmp, std::ios::trunc);
      out << "pid=" << pid << "\nholder=" << claim.holder << "\ndevice=" << device << "\n";
      if (!out.flush()) {
        ::unlink(tmp.c_str());
        continue;
      }
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
      ::unlink(tmp.c_str());
      continue;
    }
    // Older records in the other directories are stale: we hold the lock now.
    for (const auto& other : port_lock_dirs())
      if (other != dir) ::unlink((other + "/" + name).c_str());
    lock->info_path_ = path;
    break;
  }
  // No writable directory: the port is still locked, others see "another program".
  return lock;
}

}  // namespace lmcfg::transport
