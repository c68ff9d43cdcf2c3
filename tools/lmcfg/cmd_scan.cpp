// lmcfg scan: find drives on an RS485 line or gateway by trying MACIDs.
#include <cstdio>

#include "command.hpp"
#include "link_options.hpp"

namespace lmcfg::cli {
namespace {

struct ScanCli {
  CommonOptions common;
  std::string from = "0";
  std::string to = "0xFF";
};

int run(ScanCli& o) {
  auto first = parse_number(o.from, false);
  auto last = parse_number(o.to, false);
  if (!first || !last || *first > 0xFF || *last > 0xFF || *first > *last) {
    return fail("scan", Error(Errc::invalid_argument, "--from/--to must be MACIDs 0..255 with from <= to"));
  }
  // A silent ID costs a whole timeout: keep it short and do not retry.
  if (o.common.timeout_ms == 200) o.common.timeout_ms = 30;
  o.common.retries = 0;
  auto session = open_link(o.common);
  if (!session.ok()) return fail("scan", session.error());
  auto& c = (*session)->client();
  auto progress = make_progress(o.common);
  std::vector<unsigned> found;
  for (unsigned id = *first; id <= *last; ++id) {
    auto opt = c.options();
    opt.id = static_cast<std::uint8_t>(id);
    c.set_options(opt);
    if (progress) progress("scanning IDs", id - *first + 1, *last - *first + 1);
    auto r = c.default_response();
    if (r.ok()) {
      found.push_back(id);
    } else if (r.error().code == Errc::link_closed || r.error().code == Errc::io_error) {
      end_progress(o.common);
      return fail("scan", r.error());
    }
  }
  end_progress(o.common);
  if (auto closed = (*session)->close(); !closed.ok()) return fail("scan", closed.error());
  if (o.common.json) {
    std::printf("{\"found\": [");
    for (std::size_t i = 0; i < found.size(); ++i) std::printf("%s%u", i ? ", " : "", found[i]);
    std::printf("]}\n");
  } else {
    for (auto id : found) std::printf("drive at MACID 0x%02X (%u)\n", id, id);
    if (found.empty()) std::printf("no drive answered\n");
  }
  return kOk;
}

const Register reg(70, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ScanCli>();
  auto* sub = app.add_subcommand("scan", "Find drives on a line by trying MACIDs with a default response request");
  sub->footer("Example: lmcfg scan --port /dev/ttyUSB0 --from 1 --to 0x20");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--from", o->from, "first MACID")->capture_default_str();
  sub->add_option("--to", o->to, "last MACID")->capture_default_str();
  sub->callback([o, &exit_code] { exit_code = run(*o); });
});

}  // namespace
}  // namespace lmcfg::cli
