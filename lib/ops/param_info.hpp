#pragma once
// One parameter's description for `lmcfg get/set`: the UPID database's, with
// what it does not know asked from the drive (docs/upid-db.md: a UPID the database
// does not know is not an error; the tools ask the drive and say so).
#include <cstdint>
#include <string>

#include "client/client.hpp"
#include "db/database.hpp"

namespace lmcfg::ops {

struct ParamDescription {
  db::ValueSpec spec;  // the database's, completed from the drive
  std::string asked;   // what was asked ("type SINT16, min, max"); empty: nothing
};

// Asks the type (§10 05h 04h) when the database lacks it and, with
// `with_range` and an integer type, min and max (05h 05h/06h), decoded to the
// type's integers. A query the drive refuses (C1..C9) leaves that part
// unknown; a link failure is returned.
Result<ParamDescription> describe_parameter(client::Client& c, std::uint16_t upid,
                                            const db::Parameter* known, bool with_range);

}  // namespace lmcfg::ops
