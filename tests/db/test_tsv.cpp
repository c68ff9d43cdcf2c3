// The TSV source format of the UPID database (lib/db/tsv.cpp, upid-db/FORMAT.md),
// shared by the compiler and db scan's fragments.
#include <catch2/catch.hpp>
#include <vector>

#include "db/compiler.hpp"
#include "db/tsv.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_tsv {

using namespace lmcfg::db;

namespace {
std::vector<std::string> messages(const std::vector<Diagnostic>& diags) {
  std::vector<std::string> v;
  for (const auto& d : diags) v.push_back(d.str());
  return v;
}
}  // namespace

TEST_CASE("tsv: lines, comments, fields and the columns of each file", "[db]") {
  // upid-db/FORMAT.md: BOM, CRLF, comment and blank lines, TAB-separated fields.
  const std::string text = "\xEF\xBB\xBFupid\tname\r\n# comment\n\n \t \n13A2\t\xC2\xB5m Gain\n";
  auto lines = tsv::lines(tsv::strip_bom(text));
  REQUIRE(lines.size() == 5);
  CHECK(lines[0] == "upid\tname");
  CHECK_FALSE(tsv::is_data_line(lines[1]));
  CHECK_FALSE(tsv::is_data_line(lines[2]));
  CHECK_FALSE(tsv::is_data_line(lines[3]));
  CHECK(tsv::is_data_line(lines[4]));
  CHECK(tsv::split(lines[4]) == std::vector<std::string_view>{"13A2", "\xC2\xB5m Gain"});
  CHECK(tsv::split("a\t\tb\t") == std::vector<std::string_view>{"a", "", "b", ""});
  CHECK(tsv::char_column(lines[4], lines[4].size()) == 13);  // after 12 characters (µ is one)
  CHECK(tsv::field("a\tb\r\nc") == "a b  c");
  CHECK(tsv::join({"a", "", "b"}) == "a\t\tb");

  // One table per known file, in the compiler's order; db scan's fragment uses
  // the same lists.
  CHECK(tsv::source_files() == upid_db_source_files());
  for (const auto& f : tsv::source_files()) CHECK(tsv::columns_of(f) != nullptr);
  CHECK(tsv::columns_of("notes.tsv") == nullptr);
  CHECK(tsv::profile_columns() == *tsv::columns_of("profiles.tsv"));
  REQUIRE(tsv::parameter_columns().size() == 16);
  CHECK(tsv::parameter_columns().front() == "upid");
  CHECK(tsv::parameter_columns().back() == "source");

  // The reader: rows with their line and character columns; problems as
  // file:line:column diagnostics.
  std::vector<Diagnostic> diags;
  tsv::Table t(diags, "dir/x.tsv", "x.tsv", "a\tb\n# c\n1\t2\n1\t2\t3\n", {"a", "b"});
  CHECK(t.header_ok());
  REQUIRE(t.rows().size() == 1);
  CHECK(t.rows()[0].line == 3);
  CHECK(t.get(t.rows()[0], "b").text == "2");
  CHECK(t.get(t.rows()[0], "b").column == 3);
  REQUIRE(diags.size() == 1);
  CHECK(diags[0].str() ==
        "dir/x.tsv:4:5: error: expected 2 fields (as in the header, line 1), found 3");
}

TEST_CASE("tsv: a header with an unknown, a repeated or a missing column stops the file",
          "[db][tsv]") {
  std::vector<Diagnostic> diags;
  tsv::Table t(diags, "dir/x.tsv", "x.tsv", "# head\na\tz\ta\n1\t2\t3\n", {"a", "b"});
  CHECK_FALSE(t.header_ok());
  CHECK(t.rows().empty());  // rows under a bad header are not read
  CHECK(messages(diags) ==
        std::vector<std::string>{"dir/x.tsv:2:3: error: unknown column \"z\" in the header "
                                 "(expected: a b)",
                                 "dir/x.tsv:2:5: error: column \"a\" appears twice in the header",
                                 "dir/x.tsv:2:6: error: header lacks column \"b\""});
}

TEST_CASE("tsv: a row short of fields is named at its end, a file without a header is refused",
          "[db][tsv]") {
  std::vector<Diagnostic> diags;
  tsv::Table t(diags, "x.tsv", "x.tsv", "b\ta\n1\n3\t4\n", {"a", "b"});
  CHECK(t.header_ok());
  REQUIRE(t.rows().size() == 1);
  // Fields are found by column name whatever the header's order.
  CHECK(t.get(t.rows()[0], "a").text == "4");
  CHECK(t.get(t.rows()[0], "b").text == "3");
  CHECK(t.get(t.rows()[0], "c").text.empty());
  CHECK(t.get(t.rows()[0], "c").column == 1);
  CHECK(messages(diags) ==
        std::vector<std::string>{"x.tsv:2:2: error: expected 2 fields (as in the header, line 1), "
                                 "found 1"});
  t.error(t.rows()[0], t.get(t.rows()[0], "a"), "bad value");
  t.file_error("whole file");
  CHECK(diags.at(1).str() == "x.tsv:3:3: error: bad value");
  CHECK(diags.at(2).str() == "x.tsv:1:1: error: whole file");
  CHECK(t.name() == "x.tsv");

  std::vector<Diagnostic> none;
  tsv::Table empty(none, "e.tsv", "e.tsv", "# only a comment\n\n", {"a"});
  CHECK_FALSE(empty.header_ok());
  CHECK(none.empty());
  Diagnostic w{"f.tsv", 4, 2, "odd", true};
  CHECK(w.str() == "f.tsv:4:2: warning: odd");
}

}  // namespace db_test_tsv
