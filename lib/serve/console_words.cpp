#include "serve/console_words.hpp"

#include <cstring>

namespace lmcfg::serve::words {

namespace {

std::string str(const Json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

bool has(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string the_drive(const std::string& position) {
  return position.empty() ? "The drive" : "The drive at " + position;
}

// The checks of a line that does not answer, in the order a technician walks
// them: power, cable, address, speed.
std::vector<std::string> link_checklist() {
  return {"Is the drive powered? Its status LEDs are lit when it is.",
          "Is the RS485 cable plugged in at the drive and at the adapter, and the adapter "
          "connected to the service's computer?",
          "Does the drive's ID (its address switches) match the position's drive ID?",
          "Is the line's baud rate the drive's? A drive set to another rate does not answer.",
          "Is another program (LinMot-Talk) connected to the same line? Close it."};
}

}  // namespace

Errc errc_for_exit_code(int code) {
  switch (code) {
    case 2:
      return Errc::invalid_argument;
    case 3:
      return Errc::plan_refused;
    case 4:
      return Errc::timeout;
    case 5:
      return Errc::drive_refused;
    case 6:
      return Errc::verify_mismatch;
    default:
      return Errc::cancelled;
  }
}

Help help_for(const Error& e, const std::string& position) {
  const std::string& m = e.message;
  if (e.code == Errc::not_found && has(m, "expired"))
    return {
        "The plan expired: a plan is valid for a few minutes only, because the drive may "
        "change in the meantime. Nothing was written.",
        {"Make a new plan: it reads the drive again."}};
  if (e.code == Errc::not_found && has(m, "plan"))
    return {
        "This plan is no longer known to the service (it was executed already, or the "
        "service restarted). Nothing was written.",
        {"Make a new plan: it reads the drive again."}};
  if (e.code == Errc::not_found)
    return {"The service does not know what was asked for.",
            {"Check the position's name or the revision, or go back to the plant overview."}};
  if (e.code == Errc::interrupted)
    return {"The service is stopping, so it took no new work. Nothing was written.",
            {"Wait until the service runs again (ask whoever looks after it), then try again."}};
  if (e.code == Errc::invalid_argument)
    return {"Something in the form is missing or not accepted.",
            {"Read the message below, "
             "correct the form, and send "
             "it again."}};
  if (e.code == Errc::plan_refused && has(m, "is running as job"))
    return {"A restore of this drive is running now; it is not stopped between its writes.",
            {"Wait for it to end: its page shows its progress."}};
  if (e.code == Errc::plan_refused && has(m, "target changed"))
    return {the_drive(position) +
                " changed after the plan was made (it was exchanged, or written by someone "
                "else). Nothing was written.",
            {"Make a new plan: it reads the drive as it is now."}};
  if (e.code == Errc::plan_refused)
    return {"The plan cannot be carried out as it stands. Nothing was written.",
            {"Open the plan again: it says what resolves it (another revision, leaving out the "
             "values this drive cannot take, or the right drive)."}};
  const auto cls = class_of(e.code);
  if (cls == ErrorClass::drive_refusal)
    return {the_drive(position) + " answered, but refused the command.",
            {"Is the drive in an error state? Acknowledge its error (front panel or "
             "LinMot-Talk), then try again.",
             "Is another program (LinMot-Talk) connected to the drive? Close it.",
             "Is the drive's firmware one this configuration fits? The plan lists values it "
             "cannot take."}};
  if (e.code == Errc::timeout) return {the_drive(position) + " did not answer.", link_checklist()};
  if (cls == ErrorClass::bad_answer)
    return {
        "Something answers on the line, but not in a way the service can read: most often "
        "a baud rate that differs from the drive's, or another device with the same ID.",
        {"Is the line's baud rate the drive's?", "Does another drive on the line have the same ID?",
         "Is the line terminated at both ends (RS485 termination)?",
         "Is another program (LinMot-Talk) connected to the same line? Close it."}};
  if (cls == ErrorClass::link_down)
    return {
        "The service cannot reach the line: its serial port or network server does not "
        "work.",
        {"Is the USB-RS485 adapter plugged in (or the serial server reachable)?",
         "Does the service's account have the right to open the port?"}};
  return {"The service could not do what was asked.",
          {"Read the message below; if it names a bug, report it with the service's log."}};
}

Help restore_failure_help(const Json& job, const std::string& position) {
  const std::string message = str(job, "message");
  Help h;
  const auto code =
      job.contains("exit_code") && job["exit_code"].is_number() ? job["exit_code"].get<int>() : 0;
  // The CLI's exit codes (docs/cli.md): 3 plan refused, 4 link, 5 drive refused, 6 verify.
  if (code == 4)
    h = {the_drive(position) + " stopped answering during the restore.", link_checklist()};
  else if (code == 6)
    h = {"Everything was written, but the drive reads back differently.",
         {"Plan the restore again: a restore run again converges.",
          "If it reads back differently again, the drive changes the value itself: look at "
          "the differences on the position's page."}};
  else
    h = help_for(Error(errc_for_exit_code(code), message), position);
  const std::string state = str(job, "drive_state");
  if (!state.empty()) h.sentence += " The drive is " + state + ".";
  return h;
}

std::string plain(const std::string& text) {
  const std::string sign = "\u00a7";
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '(') {
      const auto close = text.find(')', i);
      if (close != std::string::npos && text.substr(i, close - i).find(sign) != std::string::npos) {
        while (!out.empty() && out.back() == ' ') out.pop_back();
        i = close + 1;
        continue;
      }
    }
    if (text.compare(i, sign.size(), sign) == 0) {
      i += sign.size();
      while (i < text.size() && text[i] != ' ' && text[i] != ',' && text[i] != ';' &&
             text[i] != ')')
        ++i;
      while (!out.empty() && out.back() == ' ') out.pop_back();
      continue;
    }
    out += text[i++];
  }
  return out;
}

namespace {

bool starts(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

std::string capital(std::string s) {
  if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

}  // namespace

std::string note(const std::string& cli_note) {
  const std::string n = cli_note;
  if (has(n, "does not know the address usage"))
    return "The parameter list does not say whether some of these values can be stored on the "
           "drive, so the service asked the drive itself. Nothing to do.";
  const std::string back = " goes back to its default";
  if (starts(n, "leftover ") && n.size() > back.size() &&
      n.compare(n.size() - back.size(), back.size(), back) == 0)
    return n.substr(9, n.size() - 9 - back.size()) +
           " is not set by the configuration: it goes back to its factory setting.";
  if (starts(n, "found the recovery record"))
    return "An earlier restore of this drive did not finish: the command table and curves are "
           "saved again and the drive restarts at the end.";
  if (starts(n, "the recovery record lists a step"))
    return "An earlier restore got no answer from the drive for one step: that step is done "
           "again.";
  if (starts(n, "MC is stopped on the target"))
    return "Motion control is stopped on the drive (an earlier restore stopped half way?): the "
           "command table and curves are saved again and the drive restarts at the end.";
  return capital(plain(n));
}

std::string progress(const std::string& cli_step) {
  const std::string t = plain(cli_step);
  static const std::pair<const char*, const char*> kPhases[] = {
      {"plan: comparing parameters",
       "Checking the drive: comparing its values with the "
       "configuration"},
      {"plan: command table", "Checking the drive: reading its command table"},
      {"plan: curves", "Checking the drive: reading its curves"},
      {"verify command table", "Reading back the command table"},
      {"verify curves", "Reading back the curves"},
      {"stop MC", "Stopping motion control (the axis stops)"},
      {"default the ", "Setting parameters to their factory defaults"},
      {"save the command table to flash",
       "Saving the command table to the drive's flash (10 s by the manual; some drives take a "
       "minute or more)"},
      {"save curves to flash",
       "Saving the curves to the drive's flash (10 s by the manual; some drives take a minute or "
       "more)"},
      {"reset the drive", "Restarting the drive (it is silent for a few seconds)"},
      {"start MC", "Starting motion control again"},
  };
  for (const auto& [prefix, words] : kPhases)
    if (starts(t, prefix)) return words;
  if (starts(t, "plan: ") && has(t, "UPID list"))
    return "Checking the drive: reading its list of " + t.substr(6, t.find(" UPID list") - 6) +
           " parameters";
  if (starts(t, "write ROM ")) return "Writing " + t.substr(10);
  for (const char* verb : {"write ", "delete "})
    if (starts(t, verb))
      return std::string(verb[0] == 'w' ? "Writing " : "Deleting ") + t.substr(std::strlen(verb));
  return capital(t);
}

std::string step(const Json& st) {
  const std::string kind = str(st, "kind");
  const std::string layer = str(st, "layer");
  const std::string id = st.contains("id") && st["id"].is_number() ? st["id"].dump() : "";
  if (kind == "stop_mc")
    return "Stop motion control: the axis stops, and stays stopped until the restore ends";
  if (kind == "start_mc") return "Start motion control again";
  if (kind == "reset") return "Restart the drive (it is silent for a few seconds)";
  if (kind == "default_layer")
    return "Set every " + (layer.empty() ? std::string("") : layer + " ") +
           "parameter to its factory default";
  if (kind == "write_rom") return "Write " + str(st, "name");
  if (kind == "delete_all_ct") return "Delete the whole command table";
  if (kind == "write_ct") return "Write command table entry " + id;
  if (kind == "delete_ct") return "Delete command table entry " + id;
  if (kind == "save_ct")
    return "Save the command table to the drive's flash (this can take a minute)";
  if (kind == "delete_all_curves") return "Delete every curve";
  if (kind == "write_curve") return "Write curve " + id;
  if (kind == "delete_curve") return "Delete curve " + id;
  if (kind == "save_curves") return "Save the curves to the drive's flash (this can take a minute)";
  return str(st, "text");
}

std::string verdict(const Json& plan, bool& refused) {
  refused = false;
  const auto count = [&plan](const char* key) {
    return plan.contains(key) && plan[key].is_array() ? plan[key].size() : std::size_t{0};
  };
  if (count("problems") > 0) {
    refused = true;
    return "Cannot be restored: " + plural(count("problems"), "problem", "problems") +
           " (below) must be resolved first. Nothing will be written.";
  }
  std::size_t values = 0, curves = 0, entries = 0, defaults = 0;
  bool stops = false, restarts = false;
  if (plan.contains("steps") && plan["steps"].is_array()) {
    for (const auto& st : plan["steps"]) {
      const std::string kind = str(st, "kind");
      values += kind == "write_rom";
      curves += kind == "write_curve";
      entries += kind == "write_ct";
      defaults += kind == "default_layer";
      stops = stops || kind == "stop_mc";
      restarts = restarts || kind == "reset";
    }
  }
  std::string what;
  auto add = [&what](const std::string& part) {
    if (!part.empty()) what += (what.empty() ? "" : ", ") + part;
  };
  if (defaults)
    add("set " + plural(defaults, "parameter layer", "parameter layers") + " to defaults");
  if (values) add("write " + plural(values, "value", "values"));
  if (curves) add("replace " + plural(curves, "curve", "curves"));
  if (entries) add("replace " + plural(entries, "command table entry", "command table entries"));
  const bool nothing = plan.value("nothing_to_do", false) || what.empty();
  const std::string effects = std::string(stops ? " The axis stops during the restore." : "") +
                              (restarts ? " The drive restarts at the end." : "");
  if (count("incompatible") > 0) {
    refused = true;
    return "Cannot be restored as it stands: this drive cannot take " +
           plural(count("incompatible"), "value", "values") +
           " of the configuration (listed below). You can restore the rest without them; the "
           "position then stays in drift until someone approves the result. " +
           (nothing ? std::string("Nothing else differs.")
                    : "The rest would " + what + "." + effects);
  }
  // What matches means (docs/fleet.md): values kept by policy are said up front.
  const std::string kept = count("kept") > 0
                               ? " " + plural(count("kept"), "value stays", "values stay") +
                                     " as the drive holds it (listed below)."
                               : std::string();
  if (nothing && kept.empty())
    return "Nothing to write: the drive already holds this configuration.";
  if (nothing)
    return "Nothing to write: the drive holds this configuration, except values it keeps by "
           "policy." +
           kept;
  return "Will " + what + "." + effects + kept;
}

std::string drive_state_after(const ops::RestoreOutcome& out, std::size_t in_flight) {
  using A = ops::PlanStep::Action;
  if (!out.written) return "untouched: nothing was written to it";
  const auto& steps = out.plan.steps;
  if (in_flight >= steps.size() || steps[in_flight].action == A::reset)
    return "written, but it has not answered since its restart: whether it holds the whole "
           "configuration is known when it answers again (a restore then reads it back)";
  bool stopped = false;
  for (std::size_t i = 0; i < steps.size() && i <= in_flight; ++i) {
    if (steps[i].action == A::stop_mc) stopped = true;
    if (steps[i].action == A::start_mc && i < in_flight) stopped = false;
  }
  return stopped ? "partially configured, and its motion control is stopped: the axis does not "
                   "move until a restore completes"
                 : "partially configured: some values were written, others not";
}

}  // namespace lmcfg::serve::words
