// The notify command (notify_command.cpp: fork and execv;
// notify_command_win32.cpp: CreateProcess, batch files through cmd.exe): the
// event on the program's stdin, its exit status in the message.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "files.hpp"
#include "serve/notify.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_notify_command {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;

#ifndef _WIN32
TEST_CASE("serve: the notify command gets the event JSON on stdin", "[serve][notify]") {
  ScratchDir d("serve-command");
  const auto script = d.path / "hook.sh";
  spit(script, "#!/bin/sh\ncat > '" + (d.path / "got.json").string() + "'\n");
  fs::permissions(script, fs::perms::owner_all);
  REQUIRE(serve::run_with_stdin(script.string(), "{\"event\":\"recovered\"}\n").ok());
  CHECK(slurp(d.path / "got.json") == "{\"event\":\"recovered\"}\n");
  spit(d.path / "fail.sh", "#!/bin/sh\nexit 3\n");
  fs::permissions(d.path / "fail.sh", fs::perms::owner_all);
  auto failed = serve::run_with_stdin((d.path / "fail.sh").string(), "{}");
  REQUIRE_FALSE(failed.ok());
  CHECK(failed.error().message ==
        "notify command " + (d.path / "fail.sh").string() + " failed (exit 3)");
}

TEST_CASE("notify: a command that cannot be run, one killed by a signal, one that reads nothing",
          "[serve][notify]") {
  ScratchDir d("notify-command");
  const std::string missing = (d.path / "no-such-program").string();
  auto r = serve::run_with_stdin(missing, "{}\n");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "notify command " + missing + " could not be run (exit 127)");

  const auto killed = shell_script(d.path, "killed.sh", "kill -9 $$\n");
  r = serve::run_with_stdin(killed.string(), "{}\n");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "notify command " + killed.string() + " failed (signal 9)");

  // No shell: the program's name is not split at blanks or expanded.
  const auto spaced =
      shell_script(d.path, "two words.sh", "cat > \"$(dirname \"$0\")/spaced.json\"\n");
  REQUIRE(serve::run_with_stdin(spaced.string(), "{\"event\":\"drift\"}\n").ok());
  CHECK(slurp(d.path / "spaced.json") == "{\"event\":\"drift\"}\n");

  // A command that exits without reading a large event: its exit status
  // counts, and the closed pipe does not end this process (SIGPIPE).
  const auto deaf = shell_script(d.path, "deaf.sh", "exit 0\n");
  CHECK(serve::run_with_stdin(deaf.string(), std::string(1 << 20, 'x')).ok());
  const auto deaf_fail = shell_script(d.path, "deaf-fail.sh", "exit 5\n");
  r = serve::run_with_stdin(deaf_fail.string(), std::string(1 << 20, 'x'));
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == "notify command " + deaf_fail.string() + " failed (exit 5)");
}

#else
namespace {
// A batch file (CRLF lines, as cmd.exe expects them).
fs::path batch(const fs::path& dir, const std::string& name, const std::string& body) {
  const auto p = dir / name;
  spit(p, "@echo off\r\n" + body + "\r\n");
  return p;
}
}  // namespace

TEST_CASE("notify command (Windows): a batch file gets the event on stdin, its exit code counts",
          "[serve][notify]") {
  ScratchDir d("notify-command-win");
  const auto got = d.path / "got.json";
  const auto hook = batch(d.path, "hook.cmd", "more > \"" + got.string() + "\"");
  REQUIRE(serve::run_with_stdin(hook.string(), "{\"event\":\"recovered\"}\n").ok());
  CHECK(slurp(got).find("{\"event\":\"recovered\"}") == 0);

  // No shell splitting: a blank in the path is part of the name.
  const auto spaced =
      batch(d.path, "two words.cmd", "more > \"" + (d.path / "spaced.json").string() + "\"");
  REQUIRE(serve::run_with_stdin(spaced.string(), "{\"event\":\"drift\"}\n").ok());
  CHECK(slurp(d.path / "spaced.json").find("{\"event\":\"drift\"}") == 0);

  const auto fail = batch(d.path, "fail.cmd", "exit /b 3");
  auto r = serve::run_with_stdin(fail.string(), "{}");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "notify command " + fail.string() + " failed (exit 3)");

  // A command that exits without reading a large event: its exit code counts.
  const auto deaf = batch(d.path, "deaf.bat", "exit /b 0");
  CHECK(serve::run_with_stdin(deaf.string(), std::string(1 << 20, 'x')).ok());
  const auto deaf_fail = batch(d.path, "deaf-fail.bat", "exit /b 5");
  r = serve::run_with_stdin(deaf_fail.string(), std::string(1 << 20, 'x'));
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == "notify command " + deaf_fail.string() + " failed (exit 5)");
}

TEST_CASE(
    "notify command (Windows): a program that cannot be run, a batch path cmd.exe would expand",
    "[serve][notify]") {
  ScratchDir d("notify-command-win-bad");
  const std::string missing = (d.path / "no-such-program.exe").string();
  auto r = serve::run_with_stdin(missing, "{}\n");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  const std::string head = "notify command " + missing + " could not be run: ";
  CHECK(r.error().message.rfind(head, 0) == 0);
  CHECK(r.error().message.size() > head.size());  // the system's reason

  const auto odd = batch(d.path, "100%.cmd", "exit /b 0");
  r = serve::run_with_stdin(odd.string(), "{}\n");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == "notify command " + odd.string() +
                                 ": a batch file's path may not contain \" % ! ^ & | < > "
                                 "(cmd.exe would read them)");
}
#endif

// check_webhook (notify.cpp): what the webhook client of this build can reach.
TEST_CASE("notify: http:// webhooks everywhere, https:// where the HTTP client has TLS",
          "[serve][notify]") {
  CHECK(serve::check_webhook("").ok());
  CHECK(serve::check_webhook("http://127.0.0.1:9000/hook").ok());
  auto r = serve::check_webhook("https://hooks.example/lmcfg");
#ifdef CPPHTTPLIB_OPENSSL_SUPPORT
  CHECK(r.ok());
#else
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  CHECK(r.error().message ==
        "[notify] webhook https://hooks.example/lmcfg: this build of lmcfg serve posts to "
        "http:// webhooks only (its HTTP client has no TLS; docs/windows.md); use an http:// "
        "receiver on this host or a [notify] command");
#endif
}

}  // namespace serve_test_notify_command
