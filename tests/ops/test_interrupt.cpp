// SIGINT/SIGTERM handling (lib/ops/interrupt.cpp): the handlers set the one
// process-wide flag, the client stops before its next telegram once it is
// set, a second signal within a second is the same Ctrl-C, a later one ends
// the process with exit 130. The signals are real (raise, kill); the exit
// path runs in a forked child.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "e2e_support.hpp"
#include "ops/interrupt.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_interrupt {

using namespace lmcfg;

namespace {

// Installs the handlers for one scope and puts the previous SIGINT/SIGTERM
// dispositions and the flag back afterwards (the test binary stays stoppable
// with Ctrl-C).
class Handlers {
 public:
  Handlers() {
    ::sigaction(SIGINT, nullptr, &old_int_);
    ::sigaction(SIGTERM, nullptr, &old_term_);
    ops::interrupt_flag() = false;
    ops::install_interrupt_handlers();
  }
  ~Handlers() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
    ops::interrupt_flag() = false;
  }
  Handlers(const Handlers&) = delete;
  Handlers& operator=(const Handlers&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace

TEST_CASE("interrupt: SIGINT and SIGTERM set the one flag and the process goes on",
          "[ops_interrupt][interrupt]") {
  CHECK(&ops::interrupt_flag() == &ops::interrupt_flag());
  Handlers h;
  CHECK_FALSE(ops::interrupt_flag().load());
  REQUIRE(::raise(SIGINT) == 0);
  CHECK(ops::interrupt_flag().load());
  // The same Ctrl-C delivered twice (GNU timeout signals the process and its
  // group) within a second: the process keeps running to name the step.
  REQUIRE(::raise(SIGINT) == 0);
  CHECK(ops::interrupt_flag().load());

  ops::interrupt_flag() = false;
  REQUIRE(::kill(::getpid(), SIGTERM) == 0);
  CHECK(ops::interrupt_flag().load());
  // SA_RESTART: the handler is installed for both signals with it.
  struct sigaction now {};
  ::sigaction(SIGTERM, nullptr, &now);
  CHECK((now.sa_flags & SA_RESTART) != 0);
  ::sigaction(SIGINT, nullptr, &now);
  CHECK((now.sa_flags & SA_RESTART) != 0);
}

TEST_CASE("interrupt: once the flag is set the client sends no further telegram",
          "[ops_interrupt][interrupt]") {
  Handlers h;
  client::ClientOptions co;
  co.cancel = &ops::interrupt_flag();
  test::SimRig rig("commissioned-axis.json", co);
  REQUIRE(rig.client->stop_mc().ok());
  REQUIRE(rig.wire->tx.size() == 1);
  REQUIRE(::raise(SIGINT) == 0);
  auto r = rig.client->start_mc();
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::interrupted);
  CHECK(r.error().code == ErrorClass::interrupted);
  CHECK(r.error().message == "interrupted by a signal before the next telegram");
  CHECK(rig.wire->tx.size() == 1);
  CHECK_FALSE(rig.drive->state().mc_running);
}

TEST_CASE("interrupt: a second signal more than a second after the first exits 130 at once",
          "[ops_interrupt][interrupt]") {
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ops::install_interrupt_handlers();
    ::raise(SIGINT);
    if (!ops::interrupt_flag().load()) ::_exit(1);
    ::raise(SIGINT);  // within the second: the same Ctrl-C, the child goes on
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    ::raise(SIGTERM);  // later: ends the process
    ::_exit(0);        // not reached
  }
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
}

}  // namespace ops_test_interrupt
