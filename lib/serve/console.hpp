#pragma once
// The web console of lmcfg serve (docs/console.md): HTML pages rendered on
// the server from the Service's calls (the ones the REST API answers), a
// small stylesheet and script embedded in the binary, sign-in with the
// tokens file into a server-side session, a CSRF token in every form.
//
// This class knows no HTTP library: the routes (serve/console_http.cpp) turn
// requests into these calls and the answers into responses. Without tokens
// every visitor is an operator (the tool allows that on loopback only) and
// there is no sign-in; the CSRF token is then one random value per process.
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "serve/service.hpp"
#include "serve/tokens.hpp"

namespace lmcfg::serve {

struct ConsoleOptions {
  std::chrono::seconds session_ttl = std::chrono::hours(8);  // a session's life from sign-in
  std::function<TimePoint()> clock = [] { return Clock::now(); };
};

// Who is looking: a signed-in token, or the anonymous operator without tokens.
struct ConsoleUser {
  std::string who;  // the token's name; "local" without tokens
  Role role = Role::viewer;
  std::string csrf;  // the value every form of this user carries
};

struct ConsoleSession {
  std::string id;   // the cookie's value
  int max_age = 0;  // seconds, for the cookie's Max-Age
  ConsoleUser user;
};

// The button of a failure page that tries the action again: a form posting
// `fields` to `action` (with the CSRF token), or a link when !post.
struct RetryForm {
  std::string action;  // "" = no button
  std::vector<std::pair<std::string, std::string>> fields;
  std::string label = "Try again";
  bool post = true;
};

// A page: the status and the HTML.
struct Page {
  int status = 200;
  std::string html;
};

class Console {
 public:
  // Errc::io_error when no random bytes can be read.
  static Result<std::unique_ptr<Console>> create(Service& service,
                                                 std::optional<std::vector<TokenEntry>> tokens,
                                                 ConsoleOptions opt);
  ~Console();

  bool sign_in_needed() const;
  // A new session for `token`; Errc::invalid_argument when the token is not in
  // the tokens file (the message says so, not which part was wrong).
  Result<ConsoleSession> sign_in(std::string_view token);
  // The session's user; nullopt when signing in is needed (no cookie, an
  // unknown or expired session). Without tokens: the anonymous operator.
  std::optional<ConsoleUser> user(std::string_view session_id);
  void sign_out(std::string_view session_id);
  // The form's CSRF value is the user's (compared in constant time).
  static bool csrf_ok(const ConsoleUser& u, std::string_view form_value);
  // The CSRF value of every form without tokens (one random value per
  // process: every visitor is the same anonymous operator).
  const std::string& anonymous_csrf() const;
  // The CSRF value for a sign-in form (nobody is signed in yet): `current`
  // (the visitor's cookie) while it is one this console issued and has not
  // taken, so that a reload or a second tab keeps the form that is already
  // open valid; else a new one for client address `addr`, valid for 10
  // minutes and one sign-in. An address holds at most kSigninNoncesPerAddress
  // (its oldest goes), the console kSigninNonces (the oldest of the address
  // holding the most goes): a client asking for many pushes out only its own.
  // Errc::io_error when no random bytes can be read.
  Result<std::string> signin_nonce(std::string_view current = {}, const std::string& addr = {});
  // Whether the sign-in form's value and its cookie's are equal and one this
  // console issued and has not yet taken (it is taken: one use).
  bool signin_nonce_ok(std::string_view cookie_value, std::string_view form_value);
  static constexpr std::size_t kSigninNonces = 256;
  static constexpr std::size_t kSigninNoncesPerAddress = 32;
  // Sessions kept at most: kMaxSessionsPerToken per token (a sign-in beyond
  // ends that token's session that expires first), kMaxSessions in all (a
  // sign-in beyond ends the session that expires first of the token holding
  // the most). Signing in with one token never ends another token's session
  // while that token holds fewer.
  static constexpr std::size_t kMaxSessions = 256;
  static constexpr std::size_t kMaxSessionsPerToken = 64;

  // Actions (the caller has checked the role and the CSRF token). The job id;
  // Errc::not_found for a name not in the inventory.
  Result<std::string> start_backup(const ConsoleUser& u, const std::string& name);
  // Plans restoring `name` from revision `rev` ("" = the archive's newest)
  // onto the drive at that position (reads it: is a drive answering, is it
  // factory-fresh?). The plan id; its page is plan_page().
  Result<std::string> make_plan(const ConsoleUser& u, const std::string& name,
                                const std::string& rev);
  // Approves revision `rev` of `name`'s file as the position's approved
  // configuration (Service::approve: a reason is required); the drift check's job id.
  Result<std::string> approve(const ConsoleUser& u, const std::string& name, const std::string& rev,
                              const std::string& reason, const std::string& ticket);
  // Cancels the automatic retry of a failed restore of `name` (Service::cancel_retry).
  Result<void> cancel_retry(const ConsoleUser& u, const std::string& name);
  // Executes a plan shown by plan_page(); the restore job's id.
  Result<std::string> start_restore(const ConsoleUser& u, const std::string& plan_id,
                                    const std::string& reason, const std::string& ticket,
                                    bool skip_incompatible);

  // Pages. `next` is where to go after signing in (a path of this console).
  Page signin_page(const std::string& message, const std::string& next, const std::string& csrf,
                   int status = 200) const;
  // `page`: the overview's page as the query gives it ("" = the first).
  Page overview(const ConsoleUser& u, const std::string& line, const std::string& status,
                const std::string& page = "") const;
  Page position(const ConsoleUser& u, const std::string& name) const;
  // The replace/restore flow's first page: which revision, then "check and plan".
  Page replace_page(const ConsoleUser& u, const std::string& name, const std::string& rev) const;
  Page plan_page(const ConsoleUser& u, const std::string& plan_id) const;
  // A revision's report and the diff of two (`to` may be "live"), as
  // `lmcfg report` renders them: whole pages with the report's own CSP.
  Result<std::string> report(const std::string& name, const std::string& rev) const;
  Result<std::string> diff(const std::string& name, const std::string& from,
                           const std::string& to) const;
  // An error of the service as a page: its status from the error's code, the
  // message as the CLI says it.
  // In plain words (what happened, what to check), with `retry`'s button and
  // the position's link; the CLI's message folded below.
  Page failure_page(const ConsoleUser& u, const std::string& title, const Error& e,
                    const RetryForm& retry = {}, const std::string& position = "") const;
  Page job_page(const ConsoleUser& u, const std::string& id, const std::string& name) const;
  Page error_page(const ConsoleUser* u, int status, const std::string& title,
                  const std::string& message) const;

  // The embedded assets (served as /console.css and /console.js).
  static std::string_view stylesheet();
  static std::string_view script();
  // The Content-Security-Policy of every console page.
  static std::string_view content_security_policy();
  // The Content-Security-Policy of the report pages (inline style only, as
  // their own meta element says).
  static std::string_view report_security_policy();

  struct Impl;

 private:
  explicit Console(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// "%XX" for everything but unreserved characters (RFC 3986 §2.3): drive
// names in links and query strings.
std::string url_encode(std::string_view s);

}  // namespace lmcfg::serve
