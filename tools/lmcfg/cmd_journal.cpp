// lmcfg journal: the local audit journal (ops/journal.hpp), newest first,
// those of one port (and MACID) with --port (--id).
#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "link_options.hpp"
#include "ops/journal.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

struct JournalCli {
  CommonOptions common;
  std::size_t limit = 0;
  CLI::Option* port = nullptr;
  CLI::Option* id = nullptr;
};

std::string text_of(const nlohmann::ordered_json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string render(const nlohmann::ordered_json& r) {
  const auto drive =
      r.contains("drive") && r["drive"].is_object() ? r["drive"] : nlohmann::ordered_json();
  std::string out = text_of(r, "time") + "  " + text_of(r, "command") + "  " +
                    text_of(drive, "port") + " " + text_of(drive, "id");
  if (const auto pos = text_of(drive, "position"); !pos.empty()) out += " (" + pos + ")";
  out += "  " + text_of(r, "who") + ": " + text_of(r, "outcome");
  if (r.contains("exit_code") && r["exit_code"].is_number_integer())
    out += " (exit " + std::to_string(r["exit_code"].get<int>()) + ")";
  out += "\n";
  const auto reason = text_of(r, "reason"), ticket = text_of(r, "ticket");
  if (!reason.empty() || !ticket.empty())
    out += "    why: " + (reason.empty() ? std::string("-") : reason) +
           (ticket.empty() ? "" : " (ticket " + ticket + ")") + "\n";
  const std::size_t steps = r.contains("steps") && r["steps"].is_array() ? r["steps"].size() : 0;
  out += "    " + std::to_string(steps) + " step(s)";
  if (const auto file = text_of(r, "file"); !file.empty()) out += ", file " + file;
  out += "\n";
  if (const auto error = text_of(r, "error"); !error.empty()) out += "    error: " + error + "\n";
  if (const auto undo = text_of(r, "undo"); !undo.empty()) out += "    undo: " + undo + "\n";
  return out;
}

int run(const JournalCli& o) {
  auto path = ops::journal_path();
  if (!path.ok()) return fail("journal", path.error());
  std::string port;
  std::optional<std::uint8_t> id;
  if (o.port->count() > 0 || o.id->count() > 0) {
    auto lo = link_options(o.common);
    if (!lo.ok()) return fail("journal", lo.error());
    if (o.port->count() > 0) port = o.common.port;
    if (o.id->count() > 0) id = lo->client.id;
  }
  auto records = ops::read_journal(*path, port, id);
  if (!records.ok()) return fail("journal", records.error());
  std::vector<nlohmann::ordered_json> newest(records->rbegin(), records->rend());
  if (o.limit > 0 && newest.size() > o.limit) newest.resize(o.limit);
  if (o.common.json) {
    std::printf("%s\n", report::journal_json(*path, newest).dump(2).c_str());
    return kOk;
  }
  if (newest.empty()) {
    std::printf("no writes recorded%s in %s\n",
                port.empty() ? "" : (" for " + port + (id ? " " + hex(*id, 2, "h") : "")).c_str(),
                path->string().c_str());
    return kOk;
  }
  std::string out;
  for (const auto& r : newest) out += (out.empty() ? "" : "\n") + render(r);
  std::fputs(out.c_str(), stdout);
  return kOk;
}

}  // namespace

void add_journal(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<JournalCli>();
  auto* sub = app.add_subcommand(
      "journal", "Show the local journal of writes: who, when, why, what and the outcome");
  sub->footer(
      "Examples:\n"
      "  lmcfg journal\n"
      "  lmcfg journal --port /dev/ttyUSB0 --id 0x11 --limit 5\n"
      "restore, fleet restore, default, set and undo append one JSON line per write to\n"
      "$XDG_STATE_HOME/lmcfg/journal.jsonl (else ~/.local/state/lmcfg/journal.jsonl), the state\n"
      "directory of the undo records; this shows it newest first (only this port's with --port,\n"
      "this MACID's with --id). --json: the records as written (docs/audit.md).");
  add_link_options(sub, o->common);
  o->port = sub->get_option("--port");
  o->port->required(false);
  o->id = sub->get_option("--id");
  add_output_options(sub, o->common);
  sub->add_option("--limit", o->limit, "show at most N records (the newest)");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace lmcfg::cli
