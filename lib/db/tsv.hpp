#pragma once
// The TSV format of the UPID database sources (upid-db/FORMAT.md): UTF-8, an
// optional BOM, one header row, one record per line, fields separated by a
// single TAB, no quoting; `#` starts a comment line, blank lines are skipped.
// One home for the file names, their columns, the line and field rules and the
// file:line:column diagnostics, shared by the compiler (lib/db/compiler*.cpp)
// and `db scan`'s fragment writer and merger (lib/ops/db_scan.cpp).
#include <string>
#include <string_view>
#include <vector>

namespace lmcfg::db {

// One problem in a source file.
struct Diagnostic {
  std::string file;  // as opened: source_dir / "parameters.tsv"
  int line = 0;      // 1-based
  int column = 0;    // 1-based, in characters (UTF-8 code points)
  std::string message;
  bool warning = false;
  // "file:line:column: error: message" (or "warning:").
  std::string str() const;
};

namespace tsv {

inline constexpr std::string_view kProfilesFile = "profiles.tsv";
inline constexpr std::string_view kParametersFile = "parameters.tsv";

// The known source files, in the compiler's processing order.
const std::vector<std::string>& source_files();
// The columns of a known file, in FORMAT.md's order; nullptr for another name.
const std::vector<std::string>* columns_of(std::string_view file);
// columns_of("profiles.tsv"), columns_of("parameters.tsv").
const std::vector<std::string>& profile_columns();
const std::vector<std::string>& parameter_columns();

// The text without a leading UTF-8 BOM.
std::string_view strip_bom(std::string_view text);
// The lines of a text, split at '\n', each without a trailing '\r'; a final
// line break does not start another line.
std::vector<std::string_view> lines(std::string_view text);
// A line that carries a header or a record: not empty, not a comment (`#`),
// not only blanks and TABs.
bool is_data_line(std::string_view line);
// The fields of a line (split at every TAB).
std::vector<std::string_view> split(std::string_view line);
// A text made fit for one field: TABs and line breaks become spaces.
std::string field(std::string_view text);
// One row (header or record) from its fields, without the line break.
std::string join(const std::vector<std::string>& fields);
// 1-based column, in characters, of the byte at `byte_off` of `line`.
int char_column(std::string_view line, std::size_t byte_off);

struct Field {
  std::string_view text;
  int column = 1;
};

struct Row {
  int line = 0;
  std::vector<Field> fields;
  int end_column = 1;  // column just after the last character
};

// One source file read against its expected columns. Problems (header
// columns unknown, duplicate or missing; a record's field count differing
// from the header's) are appended to `diags` as errors at file:line:column;
// the rows kept are the records with the header's field count.
class Table {
 public:
  Table(std::vector<Diagnostic>& diags, std::string path, std::string name, std::string content,
        const std::vector<std::string>& columns);
  Table(const Table&) = delete;
  Table& operator=(const Table&) = delete;

  const std::vector<Row>& rows() const { return rows_; }
  const std::string& path() const { return path_; }  // as opened
  const std::string& name() const { return name_; }  // "parameters.tsv"
  bool header_ok() const { return header_ok_; }

  // Field by column name (an empty field at column 1 when the header lacks it).
  const Field& get(const Row& r, std::string_view col) const;
  // An error at the field's position.
  void error(const Row& r, const Field& f, std::string msg) const;
  // An error about the whole file (at 1:1).
  void file_error(std::string msg) const;

 private:
  void parse(const std::vector<std::string>& columns);
  void check_header(const Row& r, const std::vector<std::string>& columns);

  std::vector<Diagnostic>& diags_;
  std::string path_, name_, content_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
  bool header_ok_ = true;
};

}  // namespace tsv
}  // namespace lmcfg::db
