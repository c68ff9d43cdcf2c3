// One program per port on Windows: a lock file per COM port, opened for
// writing without sharing write access while the port is open. A second
// opener's CreateFileW fails with a sharing violation; it then reads the
// holder and its PID from the file. The handle closes with the process, so a
// program that died leaves no lock. Windows itself refuses a second open of a
// COM port; Wine does not, which is why the lock comes first (serial_win32.cpp).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "transport/port_lock.hpp"
#include "transport/win32_util.hpp"

namespace lmcfg::transport {

namespace {

using win32::UniqueHandle;

// "COM7", "com7" and "\\.\COM7" are one port: one file name,
// "port-COM7.holder". Never "COM7.holder": a device name such as COM7, NUL or
// LPT1 followed by an extension names the device itself (Naming Files, Paths,
// and Namespaces: "Do not use the following reserved names ... also avoid these
// names followed immediately by an extension"), so that lock was the port.
std::string info_file_name(const std::string& device) {
  std::string name = device;
  if (auto p = com_port_path(device)) name = p->substr(4);
  std::string out = "port-";
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    out += std::isalnum(u) ? static_cast<char>(std::toupper(u)) : '_';
  }
  return out + ".holder";
}

std::optional<PortHolder> parse(const std::string& text) {
  PortHolder h;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(pos, end - pos);
    if (line.rfind("pid=", 0) == 0) h.pid = std::strtol(line.c_str() + 4, nullptr, 10);
    if (line.rfind("holder=", 0) == 0) h.holder = line.substr(7);
    pos = end + 1;
  }
  if (h.pid <= 0) return std::nullopt;
  return h;
}

// The record of a held lock: the file can be opened for reading (the holder
// shares reading) but not for writing (it does not share writing).
std::optional<PortHolder> read_held(const std::string& path) {
  const std::wstring w = win32::widen(path);
  {
    UniqueHandle probe(::CreateFileW(w.c_str(), GENERIC_WRITE, FILE_SHARE_READ | FILE_SHARE_WRITE,
                                     nullptr, OPEN_EXISTING, 0, nullptr));
    if (probe.valid()) return std::nullopt;  // nobody holds it: a stale file
    if (::GetLastError() != ERROR_SHARING_VIOLATION) return std::nullopt;
  }
  UniqueHandle h(::CreateFileW(w.c_str(), GENERIC_READ, FILE_SHARE_READ | FILE_SHARE_WRITE, nullptr,
                               OPEN_EXISTING, 0, nullptr));
  if (!h.valid()) return std::nullopt;
  char buf[1024];
  DWORD n = 0;
  if (!::ReadFile(h.get(), buf, sizeof buf, &n, nullptr)) return std::nullopt;
  return parse(std::string(buf, n));
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

}  // namespace

std::vector<std::string> port_lock_dirs() {
  std::vector<std::string> dirs;
  if (auto a = env("LOCALAPPDATA"); !a.empty()) dirs.push_back(a + "\\lmcfg\\lock");
  if (auto t = env("TEMP"); !t.empty()) dirs.push_back(t + "\\lmcfg-lock");
  return dirs;
}

std::optional<PortHolder> port_holder(const std::string& device) {
  const std::string name = info_file_name(device);
  for (const auto& dir : port_lock_dirs())
    if (auto h = read_held(dir + "\\" + name)) return h;
  return std::nullopt;
}

std::string port_in_use_message(const std::string& device) {
  return in_use_text(device, port_holder(device));
}

PortLock::~PortLock() {
  if (info_path_.empty()) return;
  // Closed first; DeleteFileW of a file another process opened since
  // (without delete sharing) then fails harmlessly.
  held_.reset();
  ::DeleteFileW(win32::widen(info_path_).c_str());
}

Result<std::unique_ptr<PortLock>> PortLock::take(int, const std::string& device,
                                                 const PortClaim& claim) {
  auto lock = std::unique_ptr<PortLock>(new PortLock);
  const std::string name = info_file_name(device);
  const std::string pid = std::to_string(::GetCurrentProcessId());
  for (const auto& dir : port_lock_dirs()) {
    // Creates each missing folder on the way (%LOCALAPPDATA%\lmcfg\lock).
    for (std::size_t p = dir.find('\\', 3);; p = dir.find('\\', p + 1)) {
      ::CreateDirectoryW(win32::widen(dir.substr(0, p)).c_str(), nullptr);
      if (p == std::string::npos) break;
    }
    const std::string path = dir + "\\" + name;
    UniqueHandle h(::CreateFileW(win32::widen(path).c_str(), GENERIC_READ | GENERIC_WRITE,
                                 FILE_SHARE_READ, nullptr, OPEN_ALWAYS, FILE_ATTRIBUTE_NORMAL,
                                 nullptr));
    if (!h.valid()) {
      if (::GetLastError() != ERROR_SHARING_VIOLATION) continue;  // try the next folder
      // The holder writes its record right after taking the lock: give it a moment.
      for (int i = 0; i < 10 && !port_holder(device); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      return Error(Errc::io_error, port_in_use_message(device));
    }
    const std::string text = claim.holder.empty() ? std::string()
                                                  : "pid=" + pid + "\nholder=" + claim.holder +
                                                        "\ndevice=" + device + "\n";
    ::SetFilePointer(h.get(), 0, nullptr, FILE_BEGIN);
    ::SetEndOfFile(h.get());
    DWORD n = 0;
    ::WriteFile(h.get(), text.data(), static_cast<DWORD>(text.size()), &n, nullptr);
    ::FlushFileBuffers(h.get());
    lock->info_path_ = path;
    lock->held_ = std::make_shared<UniqueHandle>(std::move(h));
    return lock;
  }
  // No usable folder: the port is opened unlocked, as POSIX does without a
  // writable lock-info folder (others then see "another program" from Windows).
  return lock;
}

}  // namespace lmcfg::transport
