#pragma once
// Backup (README): read a drive's configuration into the model.
//   parameters: the modified-UPID list of each layer (LinRS §10.2), or with
//               `full` every ROM-writable UPID of the UPID list (§10.3) read with
//               "read ROM value";
//   curves:     probe IDs 1..max_curve_id ("read sizes", §11; no message lists
//               curve IDs), read info and data blocks of those that exist;
//   CT:         defined-entry list (§12), then each defined entry.
// Nothing is stopped and nothing is written: backup sends read telegrams only.
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "common/families.hpp"
#include "common/progress.hpp"
#include "config/model.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// Progress: phase name, items done, items expected (0 = unknown); common/progress.hpp.
using Progress = lmcfg::Progress;

// What a backup found out about the link and the drive, for the report.
struct BackupReport {
  int reads_per_value = 1;  // 2: no checksum and no parity, each value confirmed by a second read;
                            // 3: such a link that showed corruption (a third agreeing read)
  // How the drive answers a probe of an empty curve ID / undefined CT entry
  // (00h: zero size; else the error state), when a probe found nothing.
  std::optional<std::uint8_t> empty_curve_form, empty_ct_form;
  std::vector<std::string> notes;  // sentences for people, in the order found
};

struct BackupOptions {
  std::array<bool, 4> layers{true, true, true, true};
  bool curves = true;
  bool command_table = true;
  bool full = false;
  // Record each parameter's type and factory default in the file. What the
  // database does not know is asked from the drive (§10 05h 04h / 07h; a full
  // capture takes types from the UPID list and the default of an unmodified
  // UPID from its value). false: only what the database knows, fewer telegrams.
  bool ask_drive = true;
  std::uint16_t max_curve_id = 100;  // storage limit of 100 curves (C1250 notes)
  // The drive's family (common/families.hpp; --family, the inventory's
  // `family`). nullptr: not named, taken for the seeds' E1100. A family without
  // curves, command table or stored defaults (B1100) is not asked for them: the
  // scope leaves them out and a note says so. Curves are probed up to the
  // family's storage limit. Its name goes into identity.product and its
  // upid-db profile labels the values. Not named, a drive that answers the
  // curve or command table group's first request with C3h (no_such_group) has
  // no such group: the backup goes on without it, the scope records it in
  // drive_lacks and a note says so, naming --family.
  const families::Family* family = nullptr;
  Progress progress;
  BackupReport* report = nullptr;  // filled when given
};

// Reads the drive behind `c`. db (optional) fills display names, types and
// defaults. A type or default query the drive refuses (C1..C9) leaves that
// field unknown; a link failure fails the backup.
Result<config::DriveConfig> backup(client::Client& c, const BackupOptions& opt,
                                   const db::Database& db);

// Whether a refusal says the drive has no such message group: LinRS §16.1
// "C3h Undefined Message Main ID". A B1100 has no curve and no command table
// group ("not on B1100", LinRS 3V27 §11-§12) and answers their requests so: a
// drive that answers a group's first request with C3h has no such group.
bool no_such_group(const Error& e);

// backup's readers, also used by verify (ops/restore.hpp), each reporting
// progress under `phase`. With `no_group` given, a group whose first request
// is answered C3h (no_such_group) sets *no_group and reads as empty instead of
// failing.
// The curves of IDs 1..max_curve_id ("read sizes" probes each, §11: no message
// lists curve IDs; the info and data blocks of those that exist);
Result<std::vector<config::Curve>> read_curves(client::Client& c, std::uint16_t max_curve_id,
                                               const Progress& progress, const std::string& phase,
                                               bool* no_group = nullptr);
// every entry of the defined-entry list (§12); one listed as defined whose
// query finds nothing is left out, with a sentence in `notes`.
Result<std::vector<config::CtEntry>> read_command_table(client::Client& c, const Progress& progress,
                                                        const std::string& phase,
                                                        std::vector<std::string>& notes,
                                                        bool* no_group = nullptr);

// A capture of the drive behind `c` with its identity (MACID, capture time,
// tool and database versions) and nothing in scope yet: what backup() and the
// undo records (ops/undo.hpp) start from.
config::DriveConfig new_capture(const client::Client& c, const db::Database& db);

// Fills display fields (name, unit, scaled text, type) of every parameter from
// the database; leaves unknown UPIDs untouched. The rows are those of the
// profile of the family cfg.identity.product names (common/families.hpp),
// else of the reference profile (db::Database::find).
void annotate(config::DriveConfig& cfg, const db::Database& db);

// A parameter value for people: the database's formatting (scale, unit, enum
// label) when it knows the type or a label for this value, else formatted by
// `type` (a type code recorded in a file) when given, else decimal and hex.
std::string display_value(const db::Database& db, std::uint16_t upid, std::uint32_t value,
                          std::optional<std::uint8_t> type = std::nullopt,
                          std::string_view profile = {});

// ISO 8601 UTC of now ("2026-11-22T04:05:06Z").
std::string utc_now();

}  // namespace lmcfg::ops

#include "config/model.hpp"

namespace lmcfg::ops {

// Decoded command table entries in written files (display only), through the
// database's motion command catalogue.
class DatabaseCtDecoder final : public config::CtEntryDecoder {
 public:
  explicit DatabaseCtDecoder(const db::Database& db) : db_(db) {}
  std::optional<config::CtEntryView> decode(std::uint32_t id, ByteView raw) const override;

 private:
  const db::Database& db_;
};

}  // namespace lmcfg::ops
