// The tokens file's protection and the random source (token_file.cpp: POSIX
// modes; token_file_win32.cpp: access lists, BCryptGenRandom).
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "files.hpp"
#include "serve/token_file.hpp"

#ifdef _WIN32
// windows.h lean (win32_util.hpp) before aclapi.h: a Winsock test file after
// this one in the same unity batch must not meet winsock.h.
#include "transport/win32_util.hpp"
// (a block of its own: clang-format keeps it first)
#include <aclapi.h>
#include <sddl.h>
#else
#include <sys/stat.h>
#endif

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_token_file {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;

TEST_CASE("token file: appended lines, created for its owner only, who else may write is refused",
          "[serve][tokens]") {
  ScratchDir d("token-file");
  const std::string path = (d.path / "tokens").string();
  CHECK_FALSE(serve::file_exists(path));
  CHECK(serve::check_owner_only(path).ok());  // missing: reading it says so
  REQUIRE(serve::append_owner_only(path, "a viewer 00\n").ok());
  REQUIRE(serve::append_owner_only(path, "b operator 11\n").ok());
  CHECK(serve::file_exists(path));
  CHECK(slurp(path) == "a viewer 00\nb operator 11\n");
  CHECK(serve::check_owner_only(path).ok());
#ifdef _WIN32
  namespace w32 = lmcfg::transport::win32;
  // An access list that lets a group of other users write.
  const auto grant = [&](const wchar_t* sddl) {
    PSECURITY_DESCRIPTOR sd = nullptr;
    REQUIRE(::ConvertStringSecurityDescriptorToSecurityDescriptorW(sddl, SDDL_REVISION_1, &sd,
                                                                   nullptr));
    BOOL present = FALSE, defaulted = FALSE;
    PACL dacl = nullptr;
    ::GetSecurityDescriptorDacl(sd, &present, &dacl, &defaulted);
    std::wstring w = w32::widen(path);
    const DWORD rc = ::SetNamedSecurityInfoW(w.data(), SE_FILE_OBJECT, DACL_SECURITY_INFORMATION,
                                             nullptr, nullptr, dacl, nullptr);
    ::LocalFree(sd);
    REQUIRE(rc == ERROR_SUCCESS);
  };
  const auto refused = [&](const std::string& who) {
    auto r = serve::check_owner_only(path);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::file_error);
    CHECK(r.error().message ==
          path + ": the tokens file is writable by " + who +
              " (its access list), so anyone there could add a token: run icacls \"" + path +
              "\" /inheritance:r /grant:r \"%USERNAME%:F\"");
  };
  grant(L"D:(A;;FA;;;WD)");
  refused("Everyone");
  grant(L"D:(A;;FR;;;WD)(A;;FA;;;SY)");  // read for all: passes
  CHECK(serve::check_owner_only(path).ok());
  // Wine keeps a file's access list as its Unix mode (owner, group, others =
  // Everyone): an entry for Users is dropped there, so only Windows can show it.
  const bool wine = ::GetProcAddress(::GetModuleHandleW(L"ntdll.dll"), "wine_get_version");
  if (!wine) {
    grant(L"D:(A;;FR;;;WD)(A;;0x2;;;BU)");  // Users may write data
    refused("Users");
  }
#else
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  CHECK((st.st_mode & 07777) == 0600);
  fs::permissions(path, static_cast<fs::perms>(0620));
  auto r = serve::check_owner_only(path);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message == path +
                                 ": the tokens file is writable by its group (mode 0620), so "
                                 "anyone there could add a token: run chmod 600 " +
                                 path);
  fs::permissions(path, static_cast<fs::perms>(0602));
  r = serve::check_owner_only(path);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == path +
                                 ": the tokens file is writable by others (mode 0602), so "
                                 "anyone there could add a token: run chmod 600 " +
                                 path);
  fs::permissions(path, static_cast<fs::perms>(0644));
  CHECK(serve::check_owner_only(path).ok());
#endif
}

TEST_CASE("token file: a directory that does not exist is named in the message",
          "[serve][tokens]") {
  ScratchDir d("token-file-nodir");
  const std::string path = (d.path / "no-dir" / "tokens").string();
  auto r = serve::append_owner_only(path, "a viewer 00\n");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message.rfind(path + ": ", 0) == 0);
}

TEST_CASE("token file: random bytes are as many as asked and differ between calls",
          "[serve][tokens]") {
  auto a = serve::random_bytes(32);
  auto b = serve::random_bytes(32);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->size() == 32);
  CHECK(*a != *b);  // 2^-256 to fail by chance
  CHECK(serve::random_bytes(0)->empty());
}

}  // namespace serve_test_token_file
