#pragma once
// What the restored parameters select after the drive's reset (README,
// `restore --include-comm`): the MACID and baud rate the drive takes "By
// Parameter" (LinRS §15), read from a restore plan as far as the database can
// tell. link::reconnect (link/relink.hpp) tries them first.
#include "link/relink.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

// From `plan.expected` (a UPID absent from a restored layer holds its default).
link::ExpectedLink expected_link(const Plan& plan, const db::Database& db);

}  // namespace lmcfg::ops
