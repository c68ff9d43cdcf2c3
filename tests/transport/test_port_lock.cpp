// One program per port: a serial port opened by one holder is refused to every
// other opener (another process, or another open in this one), with the
// holder's name and PID, before a byte is sent.
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "files.hpp"
#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_port_lock {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;
namespace fs = std::filesystem;
using test::make_pty;

namespace {

SerialSettings line(const std::string& device) { return {device, 57600, Parity::none, 1}; }

std::string pid_text() { return std::to_string(::getpid()); }

// The lock-info file recording the holder of `device`, in whichever lock
// directory it was written.
std::optional<fs::path> info_file(const std::string& device) {
  std::string name;
  for (char c : fs::canonical(device).string())
    name += c == '/' ? std::string("%2F") : std::string(1, c);
  for (const auto& dir : port_lock_dirs())
    if (fs::exists(fs::path(dir) / (name + ".holder"))) return fs::path(dir) / (name + ".holder");
  return std::nullopt;
}

// Nothing reached the far end of the pty (the simulated drive's side).
bool master_heard_nothing(const PtyPair& pty) {
  pollfd p{pty.master.get(), POLLIN, 0};
  return ::poll(&p, 1, 200) == 0;
}

}  // namespace

TEST_CASE("port lock: a second open is refused with the holder's name and PID, nothing sent",
          "[transport][lock]") {
  auto pty = make_pty();
  auto first = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg backup"});
  REQUIRE(first.ok());
  auto info = info_file(pty.slave_path);
  REQUIRE(info);
  const std::string recorded = test::slurp(*info);
  CHECK(recorded.find("pid=" + pid_text() + "\n") != std::string::npos);
  CHECK(recorded.find("holder=lmcfg backup\n") != std::string::npos);
  auto holder = port_holder(pty.slave_path);
  REQUIRE(holder);
  CHECK(holder->holder == "lmcfg backup");
  CHECK(holder->pid == ::getpid());

  auto second = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().code == Errc::io_error);
  CHECK(class_of(second.error().code) == ErrorClass::link_down);
  CHECK(second.error().message ==
        "port " + pty.slave_path + " is in use by lmcfg backup (PID " + pid_text() + ")");
  CHECK(master_heard_nothing(pty));

  // Closing releases the lock and removes the record; the port opens again.
  first->reset();
  CHECK_FALSE(fs::exists(*info));
  CHECK_FALSE(port_holder(pty.slave_path));
  auto third = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  REQUIRE(third.ok());
  REQUIRE((*third)->write(Bytes{0x01}).ok());
  CHECK_FALSE(master_heard_nothing(pty));
}

TEST_CASE("port lock: another process holding the port is named with its PID",
          "[transport][lock]") {
  auto pty = make_pty();
  int ready[2], done[2];
  REQUIRE(::pipe(ready) == 0);
  REQUIRE(::pipe(done) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    auto held = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg fleet backup"});
    const char ok = held.ok() ? 'y' : 'n';
    (void)!::write(ready[1], &ok, 1);
    char c;
    (void)!::read(done[0], &c, 1);  // hold the port until the parent has tried
    ::_exit(0);
  }
  char ok = 0;
  REQUIRE(::read(ready[0], &ok, 1) == 1);
  REQUIRE(ok == 'y');
  auto second = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  (void)!::write(done[1], "x", 1);
  int status = 0;
  ::waitpid(child, &status, 0);
  for (int fd : {ready[0], ready[1], done[0], done[1]}) ::close(fd);
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().message == "port " + pty.slave_path +
                                      " is in use by lmcfg fleet backup (PID " +
                                      std::to_string(child) + ")");
  CHECK(master_heard_nothing(pty));
  // The holder is gone (its exit released the flock and its record names a dead PID).
  CHECK_FALSE(port_holder(pty.slave_path));
  CHECK(open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"}).ok());
}

TEST_CASE("port lock: a holder that recorded nothing is another program, stale records are ignored",
          "[transport][lock]") {
  auto pty = make_pty();
  // A program that takes the flock itself, as terminal programs do.
  UniqueFd other(::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
  REQUIRE(other);
  REQUIRE(::flock(other.get(), LOCK_EX | LOCK_NB) == 0);
  auto refused = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message == "port " + pty.slave_path + " is in use by another program");

  // A record left by a program that died names nobody.
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  std::string name;
  for (char c : fs::canonical(pty.slave_path).string())
    name += c == '/' ? std::string("%2F") : std::string(1, c);
  const fs::path stale = fs::path(port_lock_dirs().back()) / (name + ".holder");
  fs::create_directories(stale.parent_path());
  std::ofstream(stale) << "pid=" << dead << "\nholder=lmcfg backup\n";
  CHECK_FALSE(port_holder(pty.slave_path));
  auto still = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  REQUIRE_FALSE(still.ok());
  CHECK(still.error().message == "port " + pty.slave_path + " is in use by another program");

  // Once the other program lets go, the port opens and the stale record is replaced.
  other.reset();
  auto mine = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg get"});
  REQUIRE(mine.ok());
  auto h = port_holder(pty.slave_path);
  REQUIRE(h);
  CHECK(h->holder == "lmcfg get");
  CHECK(h->pid == ::getpid());
  mine->reset();
  fs::remove(stale);
}

TEST_CASE("port lock: the lock belongs to the device, whatever path names it",
          "[transport][lock]") {
  auto pty = make_pty();
  const auto dir = test::temp_dir("port-lock");
  const fs::path alias = dir / "ttyAXIS";
  fs::create_symlink(pty.slave_path, alias);
  auto first = open_serial(line(pty.slave_path), nullptr, PortClaim{"lmcfg restore"});
  REQUIRE(first.ok());
  auto second = open_serial(line(alias.string()), nullptr, PortClaim{"lmcfg get"});
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().message ==
        "port " + alias.string() + " is in use by lmcfg restore (PID " + pid_text() + ")");
}

}  // namespace transport_test_port_lock
