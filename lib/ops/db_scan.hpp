#pragma once
// Learn a firmware profile from a drive (docs/upid-db.md, `lmcfg db scan`):
//   1. walk the UPID list of every selected layer (LinRS §10.3: UPID,
//      address usage, type);
//   2. ask min, max and default of each UPID (§10, 05h/06h/07h);
//   3. merge the names the database already knows for the same UPID (name,
//      path, unit, scale, enum labels, comm flag);
//   4. render the result as a upid-db fragment (upid-db/FORMAT.md) with
//      provenance "scanned from a drive: <profile> <date> MACID <id>".
// Resume: every UPID whose limits are read goes to a ScanStore at once; a rerun
// with the same store re-walks the UPID lists (the list cursor lives on the
// drive) but does not ask those limits again.
// Sends read telegrams only.
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "db/database.hpp"
#include "ops/backup.hpp"  // Progress

namespace lmcfg::ops {

// Raw 4-byte fields as the drive answered; nullopt = the drive refused to tell
// (answered with an error communication state).
struct ScannedLimits {
  std::optional<std::uint32_t> min, max, def;
  friend bool operator==(const ScannedLimits&, const ScannedLimits&) = default;
};

struct ScannedUpid {
  std::uint16_t upid = 0;
  std::uint16_t address_usage = 0;  // raw word from the UPID list
  std::uint16_t type = 0;           // wire type code from the UPID list
  ScannedLimits limits;
  friend bool operator==(const ScannedUpid&, const ScannedUpid&) = default;
};

// Where limits already read are kept between runs.
class ScanStore {
 public:
  virtual ~ScanStore() = default;
  // Limits stored for this UPID, only when stored with the same type and
  // address usage (otherwise the drive is not the one scanned before).
  virtual std::optional<ScannedLimits> find(std::uint16_t upid, std::uint16_t type,
                                            std::uint16_t address_usage) const = 0;
  virtual Result<void> add(const ScannedUpid& u) = 0;
  virtual std::size_t size() const = 0;
};

class MemoryScanStore : public ScanStore {
 public:
  std::optional<ScannedLimits> find(std::uint16_t upid, std::uint16_t type,
                                    std::uint16_t address_usage) const override;
  Result<void> add(const ScannedUpid& u) override;
  std::size_t size() const override { return entries_.size(); }

 private:
  std::vector<ScannedUpid> entries_;  // sorted by UPID
};

// The partial-state file (`<out>.partial`): a text file, one line per UPID
// appended (and flushed) as soon as its limits are read, so an interrupted
// scan loses at most the UPID in flight. Format:
//   # lmcfg db scan partial state, version 1
//   profile<TAB><id>
//   <UPID><TAB><address usage><TAB><type><TAB><min><TAB><max><TAB><default>
// UPID, address usage and type as 4 hex digits, values as 8 hex digits or `-`
// (refused). A malformed line (a torn last line) is ignored.
class PartialFileStore : public ScanStore {
 public:
  // Loads `path` if it exists (entries of an earlier run), else creates it.
  // A file written for another profile is refused (Errc::invalid_argument).
  static Result<std::unique_ptr<PartialFileStore>> open(const std::string& path,
                                                        const std::string& profile);
  ~PartialFileStore() override;
  PartialFileStore(const PartialFileStore&) = delete;
  PartialFileStore& operator=(const PartialFileStore&) = delete;

  std::optional<ScannedLimits> find(std::uint16_t upid, std::uint16_t type,
                                    std::uint16_t address_usage) const override;
  Result<void> add(const ScannedUpid& u) override;
  std::size_t size() const override { return mem_.size(); }
  std::size_t loaded() const { return loaded_; }  // entries read from an earlier run
  const std::string& path() const { return path_; }
  // Closes and deletes the file (after the output has been written).
  Result<void> remove();

 private:
  PartialFileStore() = default;
  std::string path_;
  std::FILE* f_ = nullptr;
  MemoryScanStore mem_;
  std::size_t loaded_ = 0;
};

// The profiles.tsv row of the new profile (empty = unknown).
struct ScanProfile {
  std::string id;  // required: lower-case id, no spaces, commas, tabs or '*'
  std::string family, software, version, description;
};

struct DbScanOptions {
  ScanProfile profile;
  std::array<bool, 4> layers{true, true, true, true};  // OS, MC, Intf, Appl
  // Known profile whose rows give names ("" = any row of the same UPID).
  std::string names_from;
  // Date in the provenance ("" = today, UTC, YYYY-MM-DD).
  std::string date;
  Progress progress;           // "UPID list <layer>" (done, 0), "min/max/default" (done, total)
  ScanStore* store = nullptr;  // resume store; nullptr = none
};

// One parameters.tsv row of the fragment.
struct ScanRow {
  ScannedUpid scanned;
  bool known = false;  // names merged from the database
  std::string name, path, unit;
  std::optional<double> scale;
  std::vector<db::EnumLabel> labels;
  bool comm = false;
};

struct DbScanResult {
  ScanProfile profile;        // family/software filled from names_from when not given
  std::string source;         // "scanned from a drive: <profile> <date> MACID <id>"
  std::vector<ScanRow> rows;  // UPID order
  std::size_t asked = 0;      // UPIDs whose limits were read in this run
  std::size_t resumed = 0;    // UPIDs whose limits came from the store
  std::size_t refused = 0;    // limits the drive refused (left unknown)
  std::size_t named = 0;      // rows with names from the database
  std::array<std::size_t, 4> per_layer{0, 0, 0, 0};
};

// Checks a profile id (shape; and, unless the database is empty, that it is not a profile
// the sources already define other than by an earlier scan).
Result<void> check_scan_profile_id(const std::string& id, const db::Database& db);

// Runs the scan. Errors: invalid_argument (profile id), link errors as the
// client reports them (the store keeps what was read).
Result<DbScanResult> scan_drive_profile(client::Client& c, const db::Database& db,
                                        const DbScanOptions& opt);

// The fragment: a parameters.tsv-format file (header + one row per UPID) whose
// leading `#@profiles.tsv<TAB>...` comment lines carry the profiles.tsv header
// and the profile row. See docs/upid-db.md "Scanning a drive".
std::string scan_fragment_tsv(const DbScanResult& r);

struct MergeReport {
  std::string profile;
  std::size_t parameters_added = 0;
  std::size_t parameters_replaced = 0;  // rows of an earlier scan of the same profile
  bool profile_replaced = false;
};

// Merges a fragment into a upid-db source directory: the profile row into
// profiles.tsv, the parameter rows into parameters.tsv (both rewritten
// atomically). Rows of an earlier scan of the same profile (profiles column
// exactly the id, source "scanned from a drive: ...") are replaced; a profile
// defined otherwise is refused (Errc::validation_failed).
Result<MergeReport> merge_scan_fragment(const std::string& source_dir,
                                        const std::string& fragment_text);

}  // namespace lmcfg::ops
