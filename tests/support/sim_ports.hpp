#pragma once
// The "sim:" port scheme (sim/state_file.hpp) is registered once for the whole
// test binary, at start-up, as lmcfg's main registers it (tools/lmcfg/main.cpp):
// every test may open sim: ports. True once registered.
namespace lmcfg::test {
extern const bool kSimPortsRegistered;
}
