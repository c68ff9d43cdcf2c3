#pragma once
// What the restored parameters select after the drive's reset (README,
// `restore --include-comm`): the MACID and baud rate the drive takes "By
// Parameter" (LinRS §15), read from a restore plan as far as the database can
// tell. ops::reconnect (ops/relink.hpp) tries them first.
#include "ops/relink.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

// From `plan.expected` (a UPID absent from a restored layer holds its default).
ExpectedLink expected_link(const Plan& plan, const db::Database& db);

}  // namespace lmcfg::ops
