// The pages of lmcfg ui (ui/pages.hpp).
#include "ui/pages.hpp"

#include "serve/console.hpp"
#include "serve/console_pages.hpp"
#include "serve/console_words.hpp"
#include "ui/ports.hpp"

namespace lmcfg::ui::pages {

namespace cp = serve::pages;
namespace words = serve::words;
using cp::esc;
using cp::member;
using cp::str;

std::string csrf_input(const std::string& csrf) {
  return "<input type=\"hidden\" name=\"csrf\" value=\"" + esc(csrf) + "\">";
}

std::string hidden(const std::string& name, const std::string& value) {
  return "<input type=\"hidden\" name=\"" + esc(name) + "\" value=\"" + esc(value) + "\">";
}

namespace {

std::string post_button(const std::string& action, const std::string& label,
                        const std::vector<std::pair<std::string, std::string>>& fields,
                        const std::string& csrf, const std::string& cls = "") {
  std::string b =
      "<form method=\"post\" action=\"" + esc(action) + "\" class=\"inline\">" + csrf_input(csrf);
  for (const auto& [k, v] : fields) b += hidden(k, v);
  return b + "<button type=\"submit\"" + (cls.empty() ? "" : " class=\"" + cls + "\"") + ">" +
         esc(label) + "</button></form>";
}

std::string drive_href(const std::string& key) {
  return "/drive?key=" + esc(serve::url_encode(key));
}

// "MACID 11h at 57600 8N1, checksum none"
std::string link_words(const Json& l) {
  char id[8];
  std::snprintf(id, sizeof id, "%02Xh", l.value("id", 0u) & 0xFFu);
  const std::string parity = str(l, "parity");
  return std::string("MACID ") + id + " at " + std::to_string(l.value("baud", 0u)) + " 8" +
         (parity == "even"  ? "E"
          : parity == "odd" ? "O"
                            : "N") +
         std::to_string(l.value("stop_bits", 1u)) + ", checksum " + str(l, "checksum");
}

// The drive's state in a sentence: "Operation Enabled, no error." or the error.
std::string state_words(const Json& info) {
  if (!info.is_object()) return "State not read yet.";
  std::string s;
  const auto& st = member(info, "state");
  if (st.is_object()) {
    const std::string name = str(st, "name");
    s = "State: " + (name.empty() ? "main state " + std::to_string(st.value("main", 0u)) : name) +
        ".";
  } else {
    s = "The drive did not report its state.";
  }
  const std::string err = str(info, "actual_error");
  s += err.empty() || err == "No Error" ? " No error." : " Error: " + err + ".";
  return s;
}

std::string drive_row(const Json& d) {
  const auto& l = member(d, "link");
  return "<tr><td><a href=\"" + drive_href(str(d, "key")) + "\"><code class=\"wrap\">" +
         esc(str(l, "port")) + "</code>" + "</a></td><td>" + esc(link_words(l)) + "</td><td>" +
         esc(state_words(member(d, "info"))) + "</td></tr>\n";
}

std::string ports_section(const Json& ports, const std::string& csrf) {
  std::string b =
      "<section aria-labelledby=\"h-ports\"><h2 id=\"h-ports\">Serial ports of this "
      "computer</h2>";
  const auto& list = member(ports, "ports");
  if (!list.is_array() || list.empty())
    b += std::string("<p id=\"no-ports\">No USB serial adapter is plugged in (none ") +
         where_ports_are_looked_for() + "). Plug one in and reload, or type a port below.</p>";
  else {
    b += "<table id=\"ports\"><thead><tr><th scope=\"col\">Port</th><th scope=\"col\">Adapter</th>"
         "<th scope=\"col\">In use</th><th scope=\"col\"></th></tr></thead><tbody>";
    for (const auto& p : list) {
      const std::string held = str(p, "held_by");
      b += "<tr class=\"port\"><td><code class=\"wrap\">" + esc(str(p, "port")) + "</code>";
      if (!str(p, "device").empty())
        b += "<br><span class=\"muted\">" + esc(str(p, "device")) + "</span>";
      b += "</td><td>" + esc(str(p, "description")) + "</td><td>" +
           (held.empty() ? "free" : "<span class=\"problem\">held by " + esc(held) + "</span>") +
           "</td><td>" + post_button("/find", "Find drives", {{"port", str(p, "port")}}, csrf) +
           "</td></tr>";
    }
    b += "</tbody></table>";
  }
  if (member(ports, "practice").is_string())
    // (A form cannot sit inside a <p>: the parser would close the paragraph.)
    b += "<div id=\"practice\"><p>No drive at hand? Practise on a simulated one: it behaves "
         "as a real drive and keeps what is written to it.</p>" +
         post_button("/find", "Find the practice drive (simulated)",
                     {{"port", str(ports, "practice")}, {"to", "63"}}, csrf) +
         "</div>";
  return b + "</section>\n";
}

std::string other_port_form(const std::string& csrf) {
  return "<section aria-labelledby=\"h-other\"><h2 id=\"h-other\">Another port or a drive on "
         "the network</h2><form method=\"post\" action=\"/find\" class=\"card\" id=\"find-form\">" +
         csrf_input(csrf) +
         "<label for=\"port\">Port or address</label><input id=\"port\" name=\"port\" required "
         "maxlength=\"300\" placeholder=\"/dev/ttyUSB0, COM3, tcp://10.0.0.5:4001, "
         "rfc2217://host:port, linudp://192.168.1.20\">"
         "<p class=\"muted\">A serial port or a serial gateway (tcp://, rfc2217://) is scanned "
         "at every rate and MACID; a LinUDP drive (linudp://ADDRESS) is asked directly.</p>"
         "<label for=\"baud\">Rate</label><select id=\"baud\" name=\"baud\"><option "
         "value=\"\">every rate (57600 first)</option><option>115200</option><option>57600"
         "</option><option>38400</option><option>19200</option><option>9600</option><option>"
         "4800</option></select><label for=\"from\">MACIDs from</label><input id=\"from\" "
         "name=\"from\" value=\"0\" inputmode=\"numeric\" maxlength=\"3\"><label for=\"to\">to"
         "</label><input id=\"to\" name=\"to\" value=\"255\" inputmode=\"numeric\" "
         "maxlength=\"3\"><button type=\"submit\">Find drives</button></form></section>\n";
}

std::string jobs_list(const Json& jobs, bool running_only) {
  std::string b;
  for (const auto& j : jobs) {
    if (running_only && str(j, "state") != "running") continue;
    b += "<li><a href=\"/job?id=" + esc(str(j, "id")) + "\">" + esc(str(j, "kind")) + " on " +
         "<code class=\"wrap\">" + esc(str(j, "port")) + "</code></a> (" + esc(str(j, "state")) +
         ")</li>";
  }
  return b;
}

}  // namespace

std::string frame(const std::string& title, const std::string& body, const std::string& csrf) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>" +
         esc(title) +
         " - lmcfg ui</title><link rel=\"stylesheet\" href=\"/console.css\">"
         "<script src=\"/console.js\" defer></script></head><body>\n"
         "<a class=\"skip\" href=\"#main\">Skip to content</a>\n"
         "<header><nav aria-label=\"lmcfg ui\"><a class=\"brand\" href=\"/\">lmcfg ui</a>"
         "<a href=\"/\">Drives</a>" +
         (csrf.empty() ? "" : post_button("/quit", "Quit", {}, csrf)) +
         "</nav></header>\n<div id=\"offline\" class=\"banner\" hidden></div>\n"
         "<main id=\"main\" tabindex=\"-1\">\n" +
         body + "</main>\n</body></html>\n";
}

std::string connect(const Json& ports, const Json& drives, const Json& jobs,
                    const std::string& folder, const std::string& csrf) {
  std::string b = "<h1>Connect a drive</h1>\n";
  const std::string running = jobs_list(jobs, true);
  if (!running.empty())
    b += "<section aria-labelledby=\"h-running\"><h2 id=\"h-running\">Running now</h2><ul "
         "id=\"running\">" +
         running + "</ul></section>\n";
  if (drives.is_array() && !drives.empty()) {
    b += "<section aria-labelledby=\"h-drives\"><h2 id=\"h-drives\">Drives found</h2><table "
         "id=\"drives\"><thead><tr><th scope=\"col\">Port</th><th scope=\"col\">Link</th><th "
         "scope=\"col\">State</th></tr></thead><tbody>\n";
    for (const auto& d : drives) b += drive_row(d);
    b += "</tbody></table></section>\n";
  }
  b += ports_section(ports, csrf);
  b += other_port_form(csrf);
  b += "<p class=\"muted\">Backups go to <code class=\"wrap\" id=\"folder\">" + esc(folder) +
       "</code> (lmcfg ui --folder DIR chooses another).</p>\n";
  return frame("Connect", b, csrf);
}

std::string failure(const std::string& title, const Error& e, int exit_code,
                    const std::string& back, const std::string& csrf) {
  std::string b = "<h1>" + esc(title) + "</h1>\n" + cp::help_html(words::help_for(e, "")) +
                  cp::cli_details(e.message, exit_code) + "<p><a class=\"button\" href=\"" +
                  esc(back.empty() ? "/" : back) + "\">Back</a></p>\n";
  return frame(title, b, csrf);
}

std::string stopped() {
  return frame("Stopped",
               "<h1>lmcfg ui has stopped</h1><p id=\"stopped\">You can close this tab. To "
               "start it again: <code>lmcfg ui</code>.</p>",
               "");
}

std::string need_token() {
  return frame("Open the page with its token",
               "<h1>Open the address lmcfg ui printed</h1><p id=\"need-token\">This page "
               "is opened with the address <code>lmcfg ui</code> printed when it started (it "
               "carries a token: http://127.0.0.1:PORT/?token=...), in the browser of the user "
               "who started it. Copy that address from its terminal.</p>",
               "");
}

}  // namespace lmcfg::ui::pages
