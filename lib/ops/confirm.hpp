#pragma once
// The answer to the confirmation every command that changes a drive asks for
// (`restore`, `default`, `link`): the library takes it from a callback
// (RestoreRunOptions::confirm) and never reads a terminal itself; the tools
// ask on the terminal (tools/lmcfg/confirm.hpp), Python through its callback.

namespace lmcfg::ops {

enum class Consent { go, declined };

}  // namespace lmcfg::ops
