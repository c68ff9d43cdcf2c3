// The notify command on Windows: CreateProcessW with the event on a pipe to
// its stdin (notify_command.cpp: fork and execv). Still no shell: a .exe runs
// as it is; a .cmd or .bat file (which only cmd.exe runs) through
// `cmd.exe /d /s /c "PATH"`, its path checked for what cmd.exe would expand.
#include <cctype>
#include <cstring>

#include "serve/notify.hpp"
#include "transport/win32_util.hpp"

namespace lmcfg::serve {

namespace w32 = lmcfg::transport::win32;

namespace {

bool ends_with_ci(const std::string& s, const char* tail) {
  const std::size_t n = std::strlen(tail);
  if (s.size() < n) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != tail[i]) return false;
  return true;
}

// An inheritable copy of one of this process's standard handles (the child
// writes where the service does), or null.
HANDLE inheritable(DWORD which) {
  HANDLE h = ::GetStdHandle(which);
  HANDLE copy = nullptr;
  if (h == nullptr || h == INVALID_HANDLE_VALUE ||
      !::DuplicateHandle(::GetCurrentProcess(), h, ::GetCurrentProcess(), &copy, 0, TRUE,
                         DUPLICATE_SAME_ACCESS))
    return nullptr;
  return copy;
}

struct Handle {
  HANDLE h = nullptr;
  ~Handle() {
    if (h && h != INVALID_HANDLE_VALUE) ::CloseHandle(h);
  }
};

}  // namespace

Result<void> run_with_stdin(const std::string& program, const std::string& input) {
  std::wstring app, cmdline;
  if (ends_with_ci(program, ".cmd") || ends_with_ci(program, ".bat")) {
    if (program.find_first_of("\"%!^&|<>") != std::string::npos)
      return Error(Errc::io_error, "notify command " + program +
                                       ": a batch file's path may not contain \" % ! ^ & | < > "
                                       "(cmd.exe would read them)");
    wchar_t sys[MAX_PATH] = L"";
    ::GetSystemDirectoryW(sys, MAX_PATH);
    app = std::wstring(sys) + L"\\cmd.exe";
    cmdline = L"cmd.exe /d /s /c \"\"" + w32::widen(program) + L"\"\"";
  } else {
    app = w32::widen(program);
    cmdline = L"\"" + app + L"\"";
  }
  SECURITY_ATTRIBUTES sa{sizeof sa, nullptr, TRUE};
  Handle rd, wr, out, err;
  if (!::CreatePipe(&rd.h, &wr.h, &sa, 0))
    return Error(Errc::io_error,
                 "notify command " + program + ": pipe: " + w32::error_text(::GetLastError()));
  // Only the child's end is inherited.
  ::SetHandleInformation(wr.h, HANDLE_FLAG_INHERIT, 0);
  out.h = inheritable(STD_OUTPUT_HANDLE);
  err.h = inheritable(STD_ERROR_HANDLE);
  STARTUPINFOW si{};
  si.cb = sizeof si;
  si.dwFlags = STARTF_USESTDHANDLES;
  si.hStdInput = rd.h;
  si.hStdOutput = out.h;
  si.hStdError = err.h;
  PROCESS_INFORMATION pi{};
  if (!::CreateProcessW(app.c_str(), cmdline.data(), nullptr, nullptr, TRUE, CREATE_NO_WINDOW,
                        nullptr, nullptr, &si, &pi))
    return Error(Errc::io_error, "notify command " + program +
                                     " could not be run: " + w32::error_text(::GetLastError()));
  Handle process{pi.hProcess}, thread{pi.hThread};
  ::CloseHandle(rd.h);
  rd.h = nullptr;
  // A command that exits without reading ends the writes (a broken pipe), not the service.
  std::size_t off = 0;
  while (off < input.size()) {
    DWORD n = 0;
    if (!::WriteFile(wr.h, input.data() + off, static_cast<DWORD>(input.size() - off), &n,
                     nullptr) ||
        n == 0)
      break;
    off += n;
  }
  ::CloseHandle(wr.h);
  wr.h = nullptr;
  ::WaitForSingleObject(pi.hProcess, INFINITE);
  DWORD code = 1;
  ::GetExitCodeProcess(pi.hProcess, &code);
  if (code == 0) return {};
  return Error(Errc::io_error,
               "notify command " + program + " failed (exit " + std::to_string(code) + ")");
}

}  // namespace lmcfg::serve
