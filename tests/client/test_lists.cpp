// The client's list reads (lib/client/lists.cpp: the modified-UPID list of
// LinRS §10.2 and the UPID list of §10.3) against the manual's conversations.
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "common/layers.hpp"
#include "manual_client.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_lists {

using namespace lmcfg;
using namespace lmcfg::client;

using Fixture = test::ManualClient;

TEST_CASE("seed003 §10.2 modified list of the Intf layer ends with C6 carrying 20C7h",
          "[client][golden]") {
  Fixture f(991, 1002);
  auto list = f.client.modified_list(lmcfg::layers::kIntf);
  REQUIRE(list.ok());
  std::vector<ModifiedParam> want{
      {0x200E, 2}, {0x2012, 8}, {0x206C, 3}, {0x2076, 0x11}, {0x20C7, 1}};
  CHECK(*list == want);
  f.done();
}

TEST_CASE("seed003 §10.3 UPID list: the C6 answer repeats 2137h and counts once",
          "[client][golden]") {
  Fixture f(1057, 1067);
  auto list = f.client.upid_list(lmcfg::layers::kIntf);
  REQUIRE(list.ok());
  std::vector<UpidInfo> want{
      {0x2008, 0x000D, 0x0A}, {0x2136, 0x1001, 0x03}, {0x2137, 0x1001, 0x03}};
  CHECK(*list == want);
  f.done();
}

}  // namespace client_test_lists
