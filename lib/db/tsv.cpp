#include "db/tsv.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace lmcfg::db {

std::string Diagnostic::str() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) +
         (warning ? ": warning: " : ": error: ") + message;
}

namespace tsv {

namespace {

// upid-db/FORMAT.md, in the compiler's processing order.
const std::vector<std::pair<std::string, std::vector<std::string>>>& formats() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> k = {
      {"profiles.tsv", {"profile", "family", "software", "version", "description", "source"}},
      {"parameters.tsv",
       {"upid", "profiles", "layer", "name", "path", "type", "address_usage", "min", "max",
        "default", "unit", "scale", "enum", "comm", "description", "source"}},
      {"errors.tsv", {"domain", "code", "class", "text", "description", "action", "source"}},
      {"motion_commands.tsv", {"master", "sub", "name", "products", "description", "source"}},
      {"motion_command_params.tsv",
       {"master", "sub", "index", "offset", "name", "type", "unit", "scale", "range", "min", "max",
        "scaled", "source"}},
      {"devicenet_parameters.tsv",
       {"id", "name", "path", "type", "min", "max", "default", "unit", "scale", "enum", "comm",
        "description", "source"}},
      {"devicenet_commands.tsv",
       {"id", "direction", "name", "table_name", "range", "min", "max", "unit", "scale",
        "unit_text", "addressed", "direct", "enum", "description", "source"}},
  };
  return k;
}

}  // namespace

const std::vector<std::string>& source_files() {
  static const std::vector<std::string> k = [] {
    std::vector<std::string> names;
    for (const auto& f : formats()) names.push_back(f.first);
    return names;
  }();
  return k;
}

const std::vector<std::string>* columns_of(std::string_view file) {
  for (const auto& f : formats())
    if (f.first == file) return &f.second;
  return nullptr;
}

const std::vector<std::string>& profile_columns() { return *columns_of(kProfilesFile); }
const std::vector<std::string>& parameter_columns() { return *columns_of(kParametersFile); }

std::string_view strip_bom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

std::vector<std::string_view> lines(std::string_view text) {
  std::vector<std::string_view> out;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    out.push_back(line);
  }
  return out;
}

bool is_data_line(std::string_view line) {
  return !line.empty() && line[0] != '#' &&
         !std::all_of(line.begin(), line.end(), [](char ch) { return ch == ' ' || ch == '\t'; });
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  while (true) {
    const std::size_t tab = line.find('\t');
    out.push_back(line.substr(0, tab));
    if (tab == std::string_view::npos) break;
    line.remove_prefix(tab + 1);
  }
  return out;
}

std::string field(std::string_view text) {
  std::string s(text);
  for (auto& ch : s)
    if (ch == '\t' || ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

std::string join(const std::vector<std::string>& fields) {
  std::string s;
  for (std::size_t i = 0; i < fields.size(); ++i) s += (i ? "\t" : "") + fields[i];
  return s;
}

int char_column(std::string_view line, std::size_t byte_off) {
  int col = 1;
  for (std::size_t i = 0; i < byte_off && i < line.size(); ++i)
    if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) ++col;
  return col;
}

Table::Table(std::vector<Diagnostic>& diags, std::string path, std::string name,
             std::string content, const std::vector<std::string>& columns)
    : diags_(diags), path_(std::move(path)), name_(std::move(name)), content_(std::move(content)) {
  parse(columns);
}

const Field& Table::get(const Row& r, std::string_view col) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == col) return r.fields[i];
  static const Field kEmpty{};
  return kEmpty;
}

void Table::error(const Row& r, const Field& f, std::string msg) const {
  diags_.push_back({path_, r.line, f.column, std::move(msg), false});
}

void Table::file_error(std::string msg) const {
  diags_.push_back({path_, 1, 1, std::move(msg), false});
}

void Table::parse(const std::vector<std::string>& columns) {
  int line_no = 0;
  bool have_header = false;
  int header_line = 0;
  for (std::string_view line : lines(strip_bom(content_))) {
    ++line_no;
    if (!is_data_line(line)) continue;
    Row r;
    r.line = line_no;
    std::size_t off = 0;
    for (std::string_view f : split(line)) {
      r.fields.push_back({f, char_column(line, off)});
      off += f.size() + 1;
    }
    r.end_column = char_column(line, line.size());
    if (!have_header) {
      have_header = true;
      header_line = line_no;
      check_header(r, columns);
      continue;
    }
    if (!header_ok_) continue;
    if (r.fields.size() != header_.size()) {
      const int col =
          r.fields.size() > header_.size() ? r.fields[header_.size()].column : r.end_column;
      diags_.push_back({path_, r.line, col,
                        "expected " + std::to_string(header_.size()) +
                            " fields (as in the header, line " + std::to_string(header_line) +
                            "), found " + std::to_string(r.fields.size()),
                        false});
      continue;
    }
    rows_.push_back(std::move(r));
  }
  if (!have_header) header_ok_ = false;
}

void Table::check_header(const Row& r, const std::vector<std::string>& columns) {
  std::set<std::string> seen;
  for (const auto& f : r.fields) {
    std::string h(f.text);
    if (std::find(columns.begin(), columns.end(), h) == columns.end()) {
      std::string expected;
      for (const auto& c : columns) expected += (expected.empty() ? "" : " ") + c;
      diags_.push_back({path_, r.line, f.column,
                        "unknown column \"" + h + "\" in the header (expected: " + expected + ")",
                        false});
      header_ok_ = false;
    } else if (!seen.insert(h).second) {
      diags_.push_back(
          {path_, r.line, f.column, "column \"" + h + "\" appears twice in the header", false});
      header_ok_ = false;
    }
    header_.push_back(h);
  }
  for (const auto& c : columns) {
    if (!seen.count(c)) {
      diags_.push_back({path_, r.line, r.end_column, "header lacks column \"" + c + "\"", false});
      header_ok_ = false;
    }
  }
}

}  // namespace tsv
}  // namespace lmcfg::db
