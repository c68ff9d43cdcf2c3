#pragma once
// Read-only access to the compiled UPID database (lmcfg-upid.sqlite, built from
// upid-db/*.tsv by upiddb-compile; schema in docs/upid-db.md). open() reads
// every table into memory and closes the file (see the contract above class
// Database).
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "common/layers.hpp"
#include "common/result.hpp"
#include "db/value.hpp"

namespace lmcfg::db {

// Version of the SQLite schema written by the compiler and required by open().
inline constexpr int kSchemaVersion = 3;
// File name looked for next to the running executable.
inline constexpr std::string_view kDefaultDbFileName = "lmcfg-upid.sqlite";
// Environment variable that overrides the default location.
inline constexpr std::string_view kDbPathEnv = "LMCFG_UPID_DB";

// Firmware layers and their UPID ranges (LinRS §10.2). `Other` holds the
// UPIDs the seeds name outside the four ranges (6300h, MC SW §3.7): no
// layer list, layer default or modified list reaches them.
// The values are the 0-based view of the layer numbers of common/layers.hpp.
enum class Layer {
  OS = layers::kOS - 1,
  MC = layers::kMC - 1,
  Intf = layers::kIntf - 1,
  Appl = layers::kAppl - 1,
  Other = layers::kCount,
};
inline constexpr std::size_t kLayerCount = layers::kCount + 1;  // with Other
// "OS", "MC", "Intf", "Appl", "Other"
std::string_view layer_name(Layer l) noexcept;
std::optional<Layer> layer_from_name(std::string_view name) noexcept;  // case-insensitive
std::optional<Layer> layer_of_upid(std::uint16_t upid) noexcept;       // nullopt between the ranges
std::uint16_t layer_base_upid(Layer l) noexcept;  // 0000, 1000, 2000, 3000; FFFF for Other

// Address usage word (LinRS §10; resolved bits only: its drawing is misaligned).
// Bit 7 vs 8 ("live parameter") is unresolved: use raw.
struct AddressUsage {
  std::uint16_t raw = 0;
  bool ram_read() const noexcept { return raw & 0x0001; }
  bool ram_write() const noexcept { return raw & 0x0002; }
  bool rom_read() const noexcept { return raw & 0x0004; }
  bool rom_write() const noexcept { return raw & 0x0008; }
  bool no_hash() const noexcept { return raw & 0x1000; }
};

// Where a row came from: the seed citation (`source` column) and the TSV line.
struct Provenance {
  std::string source;  // "seed003 §10.1", "entered by hand: ..."
  std::string file;    // "parameters.tsv"
  int line = 0;
};

struct Profile {
  std::string id, family, software, version, description;
  Provenance prov;
};

struct Parameter {
  std::uint16_t upid = 0;
  std::vector<std::string> profiles;  // empty = every profile ("*")
  Layer layer = Layer::OS;
  std::string name;
  std::string path;  // "LinRS\RS Config\..."
  ValueSpec spec;    // type, scale, unit, enum labels, min, max
  std::optional<std::int64_t> default_value;
  std::optional<AddressUsage> address_usage;
  bool comm = false;  // changing it changes how the drive talks on the line
  std::string description;
  Provenance prov;

  bool applies_to(std::string_view profile) const;
  std::string format(std::uint32_t raw) const { return format_value(spec, raw); }
};

// The profile of the seeds (E1100 with LinRS): what find() looks in when no
// profile is named.
inline constexpr std::string_view kReferenceProfile = "e1100-mc-linrs";

struct ErrorEntry {
  std::string domain;  // "mc", "linrs", "devicenet"
  std::uint32_t code = 0;
  std::string code_text;  // as written in the TSV ("000C", "C1")
  std::string text, description, action;
  Provenance prov;
  // MC SW §10's class, the prefix of `text`: "Err", "Fatal Err", "Cfg Err",
  // "Cfg Err (Fatal)", "User Err", "Setup Err", "Runtime Err"; empty where
  // the seed gives none (LinRS states, DeviceNet codes, "No Error").
  std::string error_class;
  // MC SW §3.4: a fatal error cannot be acknowledged, only a reset clears it.
  bool fatal() const noexcept { return error_class.find("Fatal") != std::string::npos; }
};

struct MotionParam {
  int index = 0;   // 1-based
  int offset = 0;  // from the command header (first parameter at 2)
  std::string name;
  ValueSpec spec;          // type, unit, scale; min/max parsed from range_text
  std::string range_text;  // as the seed's unit column writes it: "1..255", "0..", "0..3Eh"
  bool scaled = false;     // "Scaled": 16 bit interface scaling (MC SW §4.3), no fixed unit
  Provenance prov;
};

// Header layout (MC SW §4.1.1): master ID bits 15..8, sub ID bits 7..4,
// command count bits 3..0.
constexpr std::uint16_t motion_header(std::uint8_t master, std::uint8_t sub,
                                      std::uint8_t count = 0) noexcept {
  return static_cast<std::uint16_t>((master << 8) | ((sub & 0x0F) << 4) | (count & 0x0F));
}

struct MotionCommand {
  std::uint8_t master = 0;
  std::uint8_t sub = 0;
  std::string name, products, description;
  std::vector<MotionParam> params;  // ordered by index
  Provenance prov;
  std::uint16_t header() const noexcept { return motion_header(master, sub); }
};

// Seed 000, the older controllers with DeviceNet (profile e100-devicenet). Their
// parameters have no UPID: the seed addresses them by LinTalk tree path only.
// Fields the seed does not state stay empty (spec.type, default_value...).
inline constexpr std::string_view kDevicenetProfile = "e100-devicenet";

struct DevicenetParameter {
  std::string id;  // the path as printed ("DeviceNet\\Baudrate"), or the name where none is printed
  std::string name, path;
  ValueSpec spec;
  std::optional<std::int64_t> default_value;
  bool comm = false;
  std::string description;
  Provenance prov;
};

// A general-purpose command of the Addressed/Direct In/Out modules (seed 000
// §5.2 Table 5-1): a 7-bit command ID, its own address space, not a UPID.
struct DevicenetCommand {
  std::uint8_t id = 0;
  std::string id_text;                            // "0x11", as Table 5-1 writes it
  std::string direction;                          // "get", "set", or "" for neither (actions)
  std::string name;                               // detail heading
  std::string table_name, range_text, unit_text;  // Table 5-1, verbatim
  ValueSpec spec;                                 // min, max, unit, scale, labels where stated
  bool addressed = false, direct = false;         // usable in the Addressed / Direct module
  std::string description;
  Provenance prov;
};

struct DbInfo {
  std::string path;
  int schema_version = 0;
  std::string content_hash;                   // "fnv1a64:0123456789abcdef"
  std::string built_from;                     // source file list
  std::map<std::string, std::size_t> counts;  // rows per table
};

// Loading. open() checks the file and its schema version, reads every table
// into plain vectors (one copy of each row) and closes the SQLite connection:
// the database holds about a hundred parameter rows and a thousand others, so
// this costs about a millisecond (figures in docs/upid-db.md). A table that
// cannot be read fails the open. info() has the row counts.
//
// Empty database. A default-constructed Database (and empty()) has no rows:
// every lookup finds nothing, every list is empty, info() is blank. The tools
// use it when no database file could be loaded, so no function takes a
// nullable Database; is_empty() tells that case apart where output differs
// ("values shown raw").
//
// Lifetime and identity. Every pointer and reference a Database returns stays
// valid, and its object unchanged, until the Database is destroyed, also across
// a move (the moved-to Database owns it). A moved-from Database behaves as an
// empty one. find(), find_all(), search() and in_layer() return pointers into
// parameters().
//
// Threads. Nothing changes after open(): every const member function may be
// called concurrently on one Database from any number of threads. Moving,
// assigning or destroying a Database needs exclusive access, as for any
// object. The file is not needed after open(): deleting or replacing it does
// not affect an open Database.
class Database {
 public:
  static Result<Database> open(const std::string& path);
  // Opens default_path().
  static Result<Database> open_default();
  // The database a program uses when not given a path (docs/install.md):
  // $LMCFG_UPID_DB when set (taken as given: open() reports it if missing), else
  // the first existing lmcfg-upid.sqlite next to the running executable (build
  // tree), then in ../share/lmcfg/ relative to it (installed). None there:
  // file_error naming every place looked.
  static Result<std::string> default_path();
  // default_path() with the environment value (nullptr = unset) and the
  // executable's folder given.
  static Result<std::string> find_default_path(const char* env_value,
                                               const std::filesystem::path& exe_dir);

  // A database without rows (see above).
  Database() noexcept;
  // One shared empty database, for callers that have none.
  static const Database& empty() noexcept;
  // True for a default-constructed or moved-from Database.
  bool is_empty() const noexcept { return !impl_; }

  Database(Database&&) noexcept;
  Database& operator=(Database&&) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  ~Database();

  // First parameter with this UPID that applies to `profile`. Without a
  // profile, the reference profile kReferenceProfile (the seeds' E1100): a
  // name seen only for another family (UPIDs differ between families, LinRS
  // 3V27 p26: a name from another family never labels a value) labels nothing here, so a
  // caller that does not know the drive's family gets the seeds' rows only.
  // A database without that profile (built from a scan, or a test's) answers
  // with the UPID's first row.
  const Parameter* find(std::uint16_t upid, std::string_view profile = {}) const;
  // Every definition of the UPID (one per profile group), in row order.
  std::vector<const Parameter*> find_all(std::uint16_t upid) const;
  // Case-insensitive substring of name, tree path or description, in UPID order.
  std::vector<const Parameter*> search(std::string_view needle) const;
  std::vector<const Parameter*> in_layer(Layer layer) const;

  const ErrorEntry* error(std::string_view domain, std::uint32_t code) const;
  // All errors, or those of one domain (case-insensitive), ordered by domain, code.
  std::vector<const ErrorEntry*> errors(std::string_view domain = {}) const;

  // By motion command header; the command count nibble is ignored.
  const MotionCommand* motion_command(std::uint16_t header) const;
  const std::vector<MotionCommand>& motion_commands() const;  // sorted by header

  // Seed 000 (DeviceNet): parameters in seed order; commands by ID.
  const std::vector<DevicenetParameter>& devicenet_parameters() const;
  const std::vector<DevicenetCommand>& devicenet_commands() const;
  const DevicenetCommand* devicenet_command(std::uint8_t id) const;

  const std::vector<Profile>& profiles() const;
  const Profile* profile(std::string_view id) const;
  const std::vector<Parameter>& parameters() const;   // sorted by UPID
  const std::vector<ErrorEntry>& all_errors() const;  // sorted by domain, code
  const DbInfo& info() const;

  // Always nullopt: every table is read by open(), whose result carries any
  // failure. Kept for source compatibility.
  std::optional<Error> last_error() const;

 private:
  struct Impl;
  explicit Database(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::db
