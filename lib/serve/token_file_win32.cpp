// Windows: who may write the tokens file is its access list (DACL), not a
// mode. An entry that lets Everyone, Authenticated Users, Users or Guests
// write, change the list or take the file over fails the check; the file is
// created with a protected list of the user, SYSTEM and Administrators
// (what a file in the user's own profile has, without inheriting more).
#include "serve/token_file.hpp"

// windows.h (win32_util.hpp, lean: without winsock.h, which a Winsock file
// after this one in the same unity batch would meet) before the headers that
// need its types.
#include "transport/win32_util.hpp"
// (a block of its own: clang-format keeps it first)
#include <aclapi.h>
#include <bcrypt.h>
#include <sddl.h>

namespace lmcfg::serve {

namespace w32 = lmcfg::transport::win32;

namespace {

// The groups that mean "other users of this machine or domain".
const struct {
  WELL_KNOWN_SID_TYPE type;
  const char* name;
} kOthers[] = {
    {WinWorldSid, "Everyone"},
    {WinAuthenticatedUserSid, "Authenticated Users"},
    {WinBuiltinUsersSid, "Users"},
    {WinBuiltinGuestsSid, "Guests"},
};

constexpr DWORD kWriteRights =
    FILE_WRITE_DATA | FILE_APPEND_DATA | WRITE_DAC | WRITE_OWNER | GENERIC_WRITE | GENERIC_ALL;

const char* other_writer(PACL dacl) {
  for (DWORD i = 0; i < dacl->AceCount; ++i) {
    void* ace = nullptr;
    if (!::GetAce(dacl, i, &ace)) continue;
    auto* header = static_cast<ACE_HEADER*>(ace);
    if (header->AceType != ACCESS_ALLOWED_ACE_TYPE || (header->AceFlags & INHERIT_ONLY_ACE))
      continue;
    auto* allowed = static_cast<ACCESS_ALLOWED_ACE*>(ace);
    if ((allowed->Mask & kWriteRights) == 0) continue;
    PSID sid = &allowed->SidStart;
    for (const auto& other : kOthers)
      if (::IsWellKnownSid(sid, other.type)) return other.name;
  }
  return nullptr;
}

std::string user_sid() {
  HANDLE token = nullptr;
  if (!::OpenProcessToken(::GetCurrentProcess(), TOKEN_QUERY, &token)) return "";
  std::string out;
  DWORD size = 0;
  ::GetTokenInformation(token, TokenUser, nullptr, 0, &size);
  std::vector<unsigned char> buf(size);
  if (size && ::GetTokenInformation(token, TokenUser, buf.data(), size, &size)) {
    wchar_t* text = nullptr;
    if (::ConvertSidToStringSidW(reinterpret_cast<TOKEN_USER*>(buf.data())->User.Sid, &text)) {
      out = w32::narrow(text);
      ::LocalFree(text);
    }
  }
  ::CloseHandle(token);
  return out;
}

}  // namespace

Result<void> check_owner_only(const std::string& path) {
  PACL dacl = nullptr;
  PSECURITY_DESCRIPTOR sd = nullptr;
  const std::wstring wpath = w32::widen(path);
  const DWORD rc = ::GetNamedSecurityInfoW(wpath.c_str(), SE_FILE_OBJECT, DACL_SECURITY_INFORMATION,
                                           nullptr, nullptr, &dacl, nullptr, &sd);
  if (rc == ERROR_FILE_NOT_FOUND || rc == ERROR_PATH_NOT_FOUND) return {};  // reading it says so
  if (rc != ERROR_SUCCESS)
    return Error(Errc::file_error, path + ": cannot read the tokens file's access list (" +
                                       w32::error_text(rc) + "), so who may write it is unknown");
  const char* who = dacl ? other_writer(dacl) : "Everyone";
  ::LocalFree(sd);
  if (!who) return {};
  return Error(Errc::file_error, path + ": the tokens file is writable by " + who +
                                     " (its access list" +
                                     (dacl ? "" : " is empty: no restriction") +
                                     "), so anyone there could add a token: run icacls \"" + path +
                                     "\" /inheritance:r /grant:r \"%USERNAME%:F\"");
}

bool file_exists(const std::string& path) {
  return ::GetFileAttributesW(w32::widen(path).c_str()) != INVALID_FILE_ATTRIBUTES;
}

Result<void> append_owner_only(const std::string& path, const std::string& line) {
  const std::string sid = user_sid();
  const std::wstring sddl =
      w32::widen("D:P(A;;FA;;;SY)(A;;FA;;;BA)" + (sid.empty() ? "" : "(A;;FA;;;" + sid + ")"));
  PSECURITY_DESCRIPTOR sd = nullptr;
  if (!::ConvertStringSecurityDescriptorToSecurityDescriptorW(sddl.c_str(), SDDL_REVISION_1, &sd,
                                                              nullptr))
    return Error(Errc::file_error,
                 path + ": cannot make its access list: " + w32::error_text(::GetLastError()));
  SECURITY_ATTRIBUTES sa{sizeof sa, sd, FALSE};
  const HANDLE h = ::CreateFileW(w32::widen(path).c_str(), FILE_APPEND_DATA, FILE_SHARE_READ, &sa,
                                 OPEN_ALWAYS, FILE_ATTRIBUTE_NORMAL, nullptr);
  const DWORD opened = ::GetLastError();
  ::LocalFree(sd);
  if (h == INVALID_HANDLE_VALUE)
    return Error(Errc::file_error, path + ": " + w32::error_text(opened));
  DWORD n = 0;
  const bool ok =
      ::WriteFile(h, line.data(), static_cast<DWORD>(line.size()), &n, nullptr) && n == line.size();
  const DWORD written = ::GetLastError();
  ::CloseHandle(h);
  if (!ok) return Error(Errc::file_error, path + ": " + w32::error_text(written));
  return {};
}

Result<std::vector<std::uint8_t>> random_bytes(std::size_t n) {
  std::vector<std::uint8_t> raw(n);
  if (n > 0 &&
      !BCRYPT_SUCCESS(::BCryptGenRandom(nullptr, raw.data(), static_cast<ULONG>(raw.size()),
                                        BCRYPT_USE_SYSTEM_PREFERRED_RNG)))
    return Error(Errc::io_error, "BCryptGenRandom: cannot read random bytes");
  return raw;
}

}  // namespace lmcfg::serve
