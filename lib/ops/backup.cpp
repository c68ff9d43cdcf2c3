#include "ops/backup.hpp"

#include <algorithm>
#include <ctime>

#include "common/version.hpp"
#include "db/database.hpp"

namespace lmcfg::ops {

std::string utc_now() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string display_value(const db::Database* db, std::uint16_t upid, std::uint32_t value) {
  const db::Parameter* d = db ? db->find(upid) : nullptr;
  if (d) {
    const bool labelled = std::any_of(
        d->spec.labels.begin(), d->spec.labels.end(),
        [&](const db::EnumLabel& l) { return l.raw == static_cast<std::int64_t>(value); });
    if (d->spec.type || labelled) return d->format(value);
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%u (%04Xh)", value, value);
  return buf;
}

void annotate(config::DriveConfig& cfg, const db::Database& db) {
  for (auto& layer : cfg.layers) {
    for (auto& p : layer) {
      const db::Parameter* d = db.find(p.upid);
      if (!d) continue;
      p.name = d->name;
      p.unit = d->spec.unit;
      if (!p.type && d->spec.type) p.type = static_cast<std::uint8_t>(*d->spec.type);
      p.scaled = d->format(p.value);
    }
  }
}

namespace {

// FNV-1a 64 over (UPID, address usage, type) of every listed UPID: identifies
// the drive's UPID set (firmware) without listing it.
std::string fingerprint(const std::vector<client::UpidInfo>& all) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&](std::uint16_t v) {
    for (int i = 0; i < 2; ++i) {
      h ^= static_cast<std::uint8_t>(v >> (8 * i));
      h *= 0x100000001b3ull;
    }
  };
  for (const auto& u : all) {
    mix(u.upid);
    mix(u.address_usage);
    mix(u.type);
  }
  char buf[40];
  std::snprintf(buf, sizeof buf, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

void report(const Progress& p, const std::string& phase, std::size_t done, std::size_t total) {
  if (p) p(phase, done, total);
}

}  // namespace

Result<config::DriveConfig> backup(client::Client& c, const BackupOptions& opt,
                                   const db::Database* db) {
  config::DriveConfig cfg;
  char macid[8];
  std::snprintf(macid, sizeof macid, "0x%02X", c.options().id);
  cfg.identity.macid = macid;
  cfg.identity.tool_version = kToolVersion;
  cfg.identity.captured_at = utc_now();
  if (db) cfg.identity.upid_db_hash = db->info().content_hash;
  if (db) cfg.identity.upid_db_version = std::to_string(db->info().schema_version);
  cfg.scope.layers = opt.layers;
  cfg.scope.parameters = opt.full ? config::ParamSet::full : config::ParamSet::modified;
  cfg.scope.curves = opt.curves;
  cfg.scope.command_table = opt.command_table;

  std::vector<client::UpidInfo> all_upids;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    const std::string phase = std::string("parameters ") + client::layer_name(layer);
    auto& out = cfg.layer(layer);
    if (!opt.full) {
      LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
      for (const auto& m : mods)
        out.push_back(config::Parameter{m.upid, m.value, std::nullopt, {}, {}, {}});
      report(opt.progress, phase, mods.size(), mods.size());
      continue;
    }
    LMCFG_ASSIGN_OR_RETURN(auto list, c.upid_list(layer, [&](std::size_t n) {
      report(opt.progress, phase + " list", n, 0);
    }));
    all_upids.insert(all_upids.end(), list.begin(), list.end());
    std::size_t rom_writable = 0;
    for (const auto& u : list) rom_writable += (u.address_usage & 0x0008) ? 1 : 0;
    for (const auto& u : list) {
      if ((u.address_usage & 0x0008) == 0)
        continue;  // bit 3 ROM write (§10.3: only those form a configuration)
      LMCFG_ASSIGN_OR_RETURN(auto v, c.read_rom(u.upid));
      out.push_back(
          config::Parameter{u.upid, v, static_cast<std::uint8_t>(u.type & 0xFF), {}, {}, {}});
      report(opt.progress, phase, out.size(), rom_writable);
    }
  }
  if (opt.full) cfg.identity.upid_fingerprint = fingerprint(all_upids);

  if (opt.curves) {
    for (std::uint16_t id = 1; id <= opt.max_curve_id; ++id) {
      report(opt.progress, "curves", id, opt.max_curve_id);
      auto read = c.read_curve(id);
      if (!read.ok()) return std::move(read).error();
      if (read.value())
        cfg.curves.push_back(config::Curve{id, read.value()->info, read.value()->data});
    }
  }
  if (opt.command_table) {
    LMCFG_ASSIGN_OR_RETURN(auto entries, c.ct_defined_entries());
    std::size_t n = 0;
    for (auto e : entries) {
      report(opt.progress, "command table", ++n, entries.size());
      LMCFG_ASSIGN_OR_RETURN(auto raw, c.read_ct_entry(e));
      cfg.ct_entries.push_back(config::CtEntry{e, std::move(raw)});
    }
  }
  if (db) annotate(cfg, *db);
  config::canonicalize(cfg);
  return cfg;
}

}  // namespace lmcfg::ops

#include "db/ct_entry.hpp"

namespace lmcfg::ops {

std::optional<config::CtEntryView> DatabaseCtDecoder::decode(std::uint32_t, ByteView raw) const {
  auto e = db::decode_ct_entry(db_, raw);
  if (!e.ok() || !e->command) return std::nullopt;
  config::CtEntryView v;
  v.summary = e->summary();
  for (const auto& p : e->params) {
    const auto space = p.text.find(' ');
    v.params.push_back(
        config::CtParam{p.name, p.text.substr(0, space),
                        space == std::string::npos ? std::string() : p.text.substr(space + 1)});
  }
  return v;
}

}  // namespace lmcfg::ops
