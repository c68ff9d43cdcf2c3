#pragma once
// The drive configuration model: what a backup of one LinMot drive holds.
//
// Raw values are the truth: parameter values are the 4-byte fields the drive
// answered (LinRS §9/§10), curve and command table blocks are the bytes read
// with §11/§12. Decoded views (curve name, setpoints, CT summaries, scaled
// parameter text) are derived for people and never needed to restore.
//
// Files: see config/json_io.hpp, config/xml_io.hpp and config/config_io.hpp;
// the format is described in docs/config-files.md.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "common/result.hpp"

namespace lmcfg::config {

inline constexpr std::string_view kFormatId = "lmcfg-drive-config";
inline constexpr int kFormatVersion = 3;        // what the writers produce
inline constexpr int kOldestFormatVersion = 1;  // oldest the readers migrate

// ---------------------------------------------------------------------------
// Firmware layers: numbers 1..4, ranges and names in common/layers.hpp.

// ---------------------------------------------------------------------------
// Identity and provenance.
struct LinkSettings {     // as text, exactly as the capture used them
  std::string port;       // "/dev/ttyUSB0"
  std::string baud;       // "57600"
  std::string parity;     // "none"
  std::string stop_bits;  // "1"
  std::string checksum;   // "none" / "add" / "crc-ccitt-ffff" ...
  bool operator==(const LinkSettings&) const = default;
};

struct Identity {
  std::string macid;  // drive MAC ID / node id as text
  LinkSettings link;
  std::string product;                        // product profile if known ("" = unknown)
  std::string firmware;                       // firmware profile if known ("" = unknown)
  std::string upid_fingerprint;               // fingerprint of the drive's UPID set
  std::string tool_version;                   // lmcfg version that captured it
  std::string upid_db_version;                // UPID database version
  std::string upid_db_hash;                   // UPID database content hash
  std::string captured_at;                    // ISO 8601 UTC, "2024-05-01T12:00:00Z"
  std::map<std::string, std::string> labels;  // free form: machine, axis, ...
  bool operator==(const Identity&) const = default;
};

// ---------------------------------------------------------------------------
// What was captured, so a restore knows what "absent" means.
enum class ParamSet {
  modified,  // only UPIDs the drive listed as modified (§10.2): absent = default
  full,      // every ROM-writable UPID (§10.3): absent = not ROM-writable
};
std::string_view to_string(ParamSet s) noexcept;  // "modified" / "full"
std::optional<ParamSet> param_set_from_string(std::string_view s) noexcept;

struct Scope {
  std::array<bool, lmcfg::layers::kCount> layers{true, true, true, true};  // index = layer - 1
  ParamSet parameters = ParamSet::modified;
  bool curves = true;         // curves captured: absent curve = none on the drive
  bool command_table = true;  // CT captured: absent entry = undefined entry
  // Groups the drive does not have ("curves", "command_table"), so out of
  // scope with nothing to capture: it answered the group's first request with
  // C3h undefined message main ID (LinRS §16.1), or its family has none
  // (B1100, LinRS 3V27 §11-§12). Empty for files that do not say.
  std::vector<std::string> drive_lacks;
  bool operator==(const Scope&) const = default;
};

// ---------------------------------------------------------------------------
// Parameters.
struct Parameter {
  std::uint16_t upid = 0;
  std::uint32_t value = 0;           // raw 4-byte value field (§9)
  std::optional<std::uint8_t> type;  // type code 00..0F (§10) if known
  // The factory default on the source drive (§10 05h 07h, or the UPID
  // database), if known: lets a file be compared with defaults offline.
  std::optional<std::uint32_t> default_value;
  // Display only, filled by the caller (UPID database); empty = unknown.
  std::string name;
  std::string unit;
  std::string scaled;  // scaled value as text, e.g. "100.0"
  bool operator==(const Parameter&) const = default;
};

// ---------------------------------------------------------------------------
// Curves (§11). Info block layout: docs/config-files.md (LinRS §11.1, DCF).
struct Curve {
  std::uint32_t id = 0;  // 1..100 on current drives; 16 bit on the wire
  Bytes info;            // info block, as read (info size bytes, no padding)
  Bytes data;            // data block, as read
  bool operator==(const Curve&) const = default;
};

inline constexpr std::size_t kCurveHeaderMin = 8;  // sizes: off 0, 4, 6
inline constexpr std::size_t kCurveInfoFull = 70;  // everything decode_curve reads

struct CurveView {
  std::uint16_t info_size = 0;           // off 0
  std::uint16_t object_type = 0;         // off 2 (low byte 3 = curve)
  int x_code = 0;                        // high byte bits 0..3: 0 time, 1 enc pos, 2 pos
  int y_code = 0;                        // high byte bits 4..7: 0 pos, 1 vel, 2 current, ...
  std::uint16_t setpoint_count = 0;      // off 4
  std::uint16_t bytes_per_setpoint = 0;  // off 6
  std::string name;                      // off 8, char[22], NUL padded; not ASCII as \xNN
  std::uint16_t curve_id = 0;            // off 30
  std::uint32_t length = 0;              // off 32, 10 us units when X is time
  std::uint16_t x_dimension = 0;         // off 36 (0x1A = 0.01 ms)
  std::uint16_t y_dimension = 0;         // off 38 (5 = 0.1 um)
  std::uint16_t wizard = 0;              // off 40
  std::array<std::uint32_t, 7> wizard_params{};  // off 42
  std::vector<std::int32_t> setpoints;  // data block as SInt32 (when bytes/setpoint % 4 == 0)

  // length in ms as exact decimal text ("1000", "12.34").
  std::string length_ms_text() const;
  static std::string_view x_name(int code) noexcept;  // "time", "encoder position", ...
  static std::string_view y_name(int code) noexcept;  // "position", "velocity", ...
};

// Pure: decodes the raw blocks. Fails when the info block is shorter than
// kCurveInfoFull or the sizes disagree (see check_curve_blocks).
Result<CurveView> decode_curve(const Curve& c);
// Pure: the size checks a restore relies on: info off 0 == info size,
// off 4 count × off 6 bytes per setpoint == data size.
Result<void> check_curve_blocks(const Curve& c);

// ---------------------------------------------------------------------------
// Command table entries (§12).
inline constexpr std::uint32_t kMaxCtEntryId = 255;
struct CtEntry {
  std::uint32_t id = 0;  // 0..255 (wider type so files with bad IDs can be reported)
  Bytes raw;
  bool operator==(const CtEntry&) const = default;
};

// Name at off 38..53 (15 chars + NUL; LinRS §12.1 "Unnamed" at off 38,
// MC SW §4.3.143 for the offsets); "" when the entry is shorter. Bytes
// outside printable ASCII (and the backslash) are shown as "\xNN", so the
// name is clean text in both file formats.
std::string ct_entry_name(ByteView raw);

struct CtParam {
  std::string name;
  std::string value;  // as text
  std::string unit;   // "" when none
  bool operator==(const CtParam&) const = default;
};
struct CtEntryView {
  std::string summary;  // "VAI Go To Pos 100 mm"
  std::vector<CtParam> params;
  bool operator==(const CtEntryView&) const = default;
};
// Implemented by the UPID/motion-command database layer. Returns nullopt when
// it cannot decode the entry (unknown command header, ...).
class CtEntryDecoder {
 public:
  virtual ~CtEntryDecoder() = default;
  virtual std::optional<CtEntryView> decode(std::uint32_t id, ByteView raw) const = 0;
};

// ---------------------------------------------------------------------------
// DeviceNet controllers of seed 000 (the `devicenet` section, format version
// 3): runtime values read with the general-purpose commands of §5.2 Table 5-1
// over the Addressed In/Out modules. They are runtime values: the persistent
// configuration of these controllers is made with the vendor's PC software
// (DeviceNet §1.1), so a restore re-applies them until the next power cycle.
// docs/devicenet.md.
inline constexpr int kDevicenetController = -1;  // DevicenetValue::motor: no motor bit set

struct DevicenetValue {
  int motor = kDevicenetController;  // -1: the controller, 0..3: motor A..D
  std::uint8_t command = 0;          // the Get command ID (Table 5-1); its Set is command + 1
  std::uint16_t raw = 0;             // the response value word as read (§5.2 word 2)
  // Display only, filled from the database; empty = unknown.
  std::string name;    // "Controller P"
  std::string unit;    // "A/mm"
  std::string scaled;  // "2.3438"
  bool operator==(const DevicenetValue&) const = default;
};

struct DevicenetSection {
  std::uint32_t can_bitrate = 125000;  // 125000, 250000 or 500000
  // The controller's IO modules as configured with LinTalk (§5.1), by name:
  // "control-in", "addressed-in", "direct-in:A".., "status-out",
  // "addressed-out", "direct-out-1:A".., "direct-out-2:A"..
  // (devicenet::IoLayout's text form).
  std::vector<std::string> io_modules;
  std::vector<int> motors;  // motors configured on the controller, 0..3 = A..D, ascending
  // Settable values (a Get with a Set of Table 5-1): compared and restored.
  std::vector<DevicenetValue> values;
  // Informational (status words, actual position, setpoints, IO): recorded
  // when read, never restored, compared only when asked.
  std::vector<DevicenetValue> live;
  bool operator==(const DevicenetSection&) const = default;
};

// ---------------------------------------------------------------------------
struct DriveConfig {
  Identity identity;
  Scope scope;
  std::array<std::vector<Parameter>, lmcfg::layers::kCount> layers;  // index = layer - 1
  std::vector<Curve> curves;
  std::vector<CtEntry> ct_entries;
  // Present for DeviceNet controllers (seed 000) only; such a capture has no
  // layers, curves or command table in its scope.
  std::optional<DevicenetSection> devicenet;

  std::vector<Parameter>& layer(int number) {
    return layers.at(static_cast<std::size_t>(number - 1));
  }
  const std::vector<Parameter>& layer(int number) const {
    return layers.at(static_cast<std::size_t>(number - 1));
  }
  // Lookups (linear; the model is small). nullptr when absent.
  const Parameter* find_param(std::uint16_t upid) const;
  const Curve* find_curve(std::uint32_t id) const;
  const CtEntry* find_ct_entry(std::uint32_t id) const;

  bool operator==(const DriveConfig&) const = default;
};

// Sorts UPIDs ascending within each layer, curves and entries by ID: the
// canonical order the writers use. Validation keeps file order for messages.
void canonicalize(DriveConfig& cfg);

// A semantic problem, located in model terms so each reader can turn it into
// its own location (JSON pointer -> line:column, XML path).
struct Issue {
  enum class Where { identity, scope, layer, param, curve, ct_entry, devicenet, devicenet_value };
  Where where = Where::scope;
  int layer = 0;          // 1..4 for layer/param
  std::size_t index = 0;  // position within the layer / curves / ct_entries / devicenet values
  std::string field;      // "upid", "value", "id", "info", "data", "raw", "" (identity: "macid",
                          // "link.port", "labels.<key>", ...)
  std::string message;    // what was expected
  bool live = false;      // devicenet_value: in `live`, not `values`
};
// Text fields (identity, labels, display fields) must be valid UTF-8 without
// control characters, so that both formats carry them losslessly.
bool is_clean_text(std::string_view s) noexcept;
// First problem found, in document order; nullopt when the model is valid.
std::optional<Issue> find_issue(const DriveConfig& cfg);
// Same, as an Error (Errc::validation_failed) with a model path, for callers
// that hold a model (writers refuse to write an invalid model).
Result<void> validate(const DriveConfig& cfg);

}  // namespace lmcfg::config
