#include "db/compiler.hpp"

// The UPID database compiler's driver: reads each known source file
// (lib/db/tsv.hpp), validates its rows (compiler_rows.cpp) and writes the
// SQLite file (compiler_write.cpp) through a temporary file and a rename.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "db/compiler_model.hpp"
#include "db/database.hpp"
#include "db/tsv.hpp"

namespace lmcfg::db {

namespace fs = std::filesystem;

bool CompileReport::ok() const {
  return std::none_of(diagnostics.begin(), diagnostics.end(),
                      [](const Diagnostic& d) { return !d.warning; });
}

std::uint64_t fnv1a64(std::string_view data, std::uint64_t h) noexcept {
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

const std::vector<std::string>& upid_db_source_files() { return tsv::source_files(); }

CompileReport compile_upid_db(const std::string& source_dir, const std::string& out_path) {
  CompileReport rep;
  auto error = [&rep](const std::string& file, std::string msg) {
    rep.diagnostics.push_back({file, 0, 0, std::move(msg), false});
  };
  compiler::Model m;
  std::uint64_t h = fnv1a64("lmcfg-upid schema " + std::to_string(kSchemaVersion));
  std::string built_from;
  std::error_code ec;
  if (!fs::is_directory(source_dir, ec)) {
    error(source_dir, "not a directory");
    return rep;
  }
  // Unknown *.tsv files: warn, do not fail (other tables may be added later).
  std::vector<std::string> unknown;
  for (const auto& de : fs::directory_iterator(source_dir, ec)) {
    std::string n = de.path().filename().string();
    if (de.path().extension() == ".tsv" && !tsv::columns_of(n)) unknown.push_back(n);
  }
  std::sort(unknown.begin(), unknown.end());
  for (const auto& n : unknown)
    rep.diagnostics.push_back({(fs::path(source_dir) / n).string(), 1, 1,
                               "not a table the compiler knows; ignored", true});

  for (const auto& name : upid_db_source_files()) {
    std::string path = (fs::path(source_dir) / name).string();
    if (!fs::exists(path, ec)) continue;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      error(path, "cannot read the file");
      continue;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    std::string content = ss.str();
    h = fnv1a64(name, h);
    h = fnv1a64(std::string_view("\0", 1), h);
    h = fnv1a64(content, h);
    h = fnv1a64(std::string_view("\0", 1), h);
    built_from += (built_from.empty() ? "" : " ") + name;
    tsv::Table t(rep.diagnostics, path, name, std::move(content), *tsv::columns_of(name));
    if (t.header_ok()) compiler::load_table(t, m);
  }
  char hb[40];
  std::snprintf(hb, sizeof hb, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  rep.content_hash = hb;
  std::size_t nlabels = 0, ncparams = 0;
  for (const auto& p : m.params) nlabels += p.spec.labels.size();
  for (const auto& cmd : m.commands) ncparams += cmd.params.size();
  rep.counts = {{"profiles", m.profiles.size()},
                {"parameters", m.params.size()},
                {"enum_labels", nlabels},
                {"errors", m.errors.size()},
                {"motion_commands", m.commands.size()},
                {"motion_command_params", ncparams},
                {"devicenet_parameters", m.dn_params.size()},
                {"devicenet_commands", m.dn_commands.size()}};
  if (!rep.ok() || out_path.empty()) return rep;

  std::sort(m.params.begin(), m.params.end(),
            [](const Parameter& a, const Parameter& b) { return a.upid < b.upid; });
  std::string tmp = out_path + ".tmp." + std::to_string(::getpid());
  fs::remove(tmp, ec);
  std::string werr = compiler::write_db(m, tmp, rep.content_hash, built_from);
  if (werr.empty()) {
    fs::rename(tmp, out_path, ec);
    if (ec) werr = "cannot rename " + tmp + " to " + out_path + ": " + ec.message();
  }
  if (!werr.empty()) {
    fs::remove(tmp, ec);
    error(out_path, werr);
    return rep;
  }
  rep.written = true;
  return rep;
}

}  // namespace lmcfg::db
