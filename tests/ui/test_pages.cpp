// The pages of lmcfg ui (ui/pages.hpp) from the desk's JSON: what each says,
// the forms' CSRF value, and every text from a drive, a file or a port
// escaped.
#include <catch2/catch.hpp>

#include "ui/pages.hpp"

namespace ui_test_pages {

using namespace lmcfg;
using ui::Json;

bool has(const std::string& html, const std::string& part) {
  return html.find(part) != std::string::npos;
}

TEST_CASE("pages: connect lists ports, holders, the practice drive and the drives found",
          "[ui_pages]") {
  Json ports{{"ports", Json::array({Json{{"port", "/dev/serial/by-id/usb-<x>"},
                                         {"device", "/dev/ttyUSB0"},
                                         {"description", "FTDI FT232R USB UART"},
                                         {"held_by", "minicom (PID 77)"}}})},
             {"practice", "sim:/home/t/lmcfg/practice/drive.json"}};
  Json drives = Json::array(
      {Json{{"key", "k-11h"},
            {"link",
             {{"port", "sim:a"},
              {"baud", 57600},
              {"parity", "none"},
              {"stop_bits", 1},
              {"checksum", "none"},
              {"id", 17}}},
            {"info", {{"state", {{"name", "Operation Enabled"}}}, {"actual_error", ""}}}}});
  Json jobs =
      Json::array({Json{{"id", "3"}, {"kind", "backup"}, {"port", "sim:a"}, {"state", "running"}}});
  const std::string html = ui::pages::connect(ports, drives, jobs, "/home/t/lmcfg", "C5RF");
  CHECK(has(html, "usb-&lt;x&gt;"));
  CHECK_FALSE(has(html, "usb-<x>"));
  CHECK(has(html, "held by minicom (PID 77)"));
  CHECK(has(html, "Find the practice drive (simulated)"));
  CHECK(has(html, "MACID 11h at 57600 8N1, checksum none"));
  CHECK(has(html, "State: Operation Enabled. No error."));
  CHECK(
      has(html, "<a href=\"/job?id=3\">backup on <code class=\"wrap\">sim:a</code></a> (running)"));
  CHECK(has(html, "name=\"csrf\" value=\"C5RF\""));
  CHECK(has(html, "action=\"/quit\""));
}

TEST_CASE("pages: a failed write says what the drive holds and how to go on", "[ui_pages]") {
  Json j{{"id", "7"},
         {"kind", "restore"},
         {"drive", "k-11h"},
         {"port", "sim:a"},
         {"state", "failed"},
         {"message", "no answer from drive 11h"},
         {"exit_code", 4},
         {"drive_state", "partially configured, and its motion control is stopped"},
         {"progress", {{"step", ""}, {"done", 3}, {"total", 9}}},
         {"result", Json::object()}};
  const std::string html = ui::pages::job(j, "C");
  CHECK(has(html, "stopped answering during the restore."));
  CHECK(has(html, "The drive is partially configured, and its motion control is stopped."));
  CHECK(has(html, "lmcfg restore FILE"));
  CHECK(has(html, "As the command line says it"));
  CHECK_FALSE(has(html, "data-refresh"));
}

TEST_CASE("pages: a running job refreshes itself, and a write says closing the tab stops nothing",
          "[ui_pages]") {
  Json j{{"id", "8"},
         {"kind", "restore"},
         {"drive", "k"},
         {"port", "p"},
         {"state", "running"},
         {"progress", {{"step", "write 2000h"}, {"done", 2}, {"total", 5}}},
         {"result", Json::object()}};
  const std::string html = ui::pages::job(j, "C");
  CHECK(has(html, "data-refresh=\"1\""));
  CHECK(has(html, "<progress max=\"5\" value=\"2\">"));
  CHECK(has(html, "Closing this tab does not stop the write"));
}

TEST_CASE("pages: the plan's verdict first, its write button behind a reason", "[ui_pages]") {
  Json p{{"plan_id", "p1"},
         {"drive", "k-11h"},
         {"port", "sim:a"},
         {"id", "11h"},
         {"file", "k-11h-1.json"},
         {"undo", false},
         {"expires_in_s", 600},
         {"nothing_to_do", false},
         {"steps", Json::array({Json{{"kind", "write_rom"},
                                     {"upid", "2000"},
                                     {"name", "Speed"},
                                     {"old", "1"},
                                     {"new", "2"},
                                     {"unit", "m/s"},
                                     {"text", "write 2000h"}}})},
         {"losses", Json::array()},
         {"notes", Json::array({"kept: <comm>"})},
         {"problems", Json::array()},
         {"incompatible", Json::array()},
         {"factory_fresh", true}};
  const std::string html = ui::pages::plan(p, "C");
  CHECK(html.find("id=\"verdict\"") < html.find("<table class=\"plan\">"));
  CHECK(has(html, "<span class=\"pname\">Speed</span>"));
  CHECK(has(html, "factory-fresh</strong>"));
  CHECK(has(html, "kept: &lt;comm&gt;"));
  CHECK(has(html, "name=\"reason\" required"));
  CHECK(has(html, "<input type=\"hidden\" name=\"plan\" value=\"p1\">"));
  p["problems"] = Json::array({Json{{"message", "the file is not a LinRS configuration"}}});
  CHECK_FALSE(has(ui::pages::plan(p, "C"), "id=\"execute\""));
}

}  // namespace ui_test_pages
