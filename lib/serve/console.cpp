#include "serve/console.hpp"

#include <map>
#include <mutex>

#include "serve/console_pages.hpp"

namespace lmcfg::serve {

namespace {

// Equal strings, in a time that says nothing about where they differ.
bool same(std::string_view a, std::string_view b) {
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    diff |= static_cast<unsigned>(a[i] ^ b[i]);
  return diff == 0 && !a.empty();
}

}  // namespace

struct Console::Impl {
  Service& service;
  std::optional<std::vector<TokenEntry>> tokens;
  ConsoleOptions opt;
  std::string anonymous_csrf;  // the sign-in form's, and every form's without tokens

  struct Session {
    ConsoleUser user;
    TimePoint expires;
  };
  std::mutex mu;
  std::map<std::string, Session, std::less<>> sessions;

  Impl(Service& s, std::optional<std::vector<TokenEntry>> t, ConsoleOptions o)
      : service(s), tokens(std::move(t)), opt(std::move(o)) {}
};

Console::Console(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Console::~Console() = default;

Result<std::unique_ptr<Console>> Console::create(Service& service,
                                                 std::optional<std::vector<TokenEntry>> tokens,
                                                 ConsoleOptions opt) {
  auto impl = std::make_unique<Impl>(service, std::move(tokens), std::move(opt));
  LMCFG_ASSIGN_OR_RETURN(impl->anonymous_csrf, random_hex(32));
  return std::unique_ptr<Console>(new Console(std::move(impl)));
}

bool Console::sign_in_needed() const { return impl_->tokens.has_value(); }

const std::string& Console::anonymous_csrf() const { return impl_->anonymous_csrf; }

Result<ConsoleSession> Console::sign_in(std::string_view token) {
  if (!impl_->tokens) return Error(Errc::invalid_argument, "this console has no sign-in");
  const TokenEntry* e = find_token(*impl_->tokens, token);
  if (!e) return Error(Errc::invalid_argument, "that token is not in the tokens file");
  ConsoleSession s;
  LMCFG_ASSIGN_OR_RETURN(s.id, random_hex(32));
  LMCFG_ASSIGN_OR_RETURN(s.user.csrf, random_hex(32));
  s.user.who = e->name;
  s.user.role = e->role;
  s.max_age = static_cast<int>(impl_->opt.session_ttl.count());
  const TimePoint now = impl_->opt.clock();
  std::lock_guard<std::mutex> lock(impl_->mu);
  // Expired sessions go when someone signs in: the map stays as small as the
  // number of people signed in during one session's life.
  for (auto it = impl_->sessions.begin(); it != impl_->sessions.end();)
    it = it->second.expires <= now ? impl_->sessions.erase(it) : std::next(it);
  impl_->sessions[s.id] = {s.user, now + impl_->opt.session_ttl};
  return s;
}

std::optional<ConsoleUser> Console::user(std::string_view session_id) {
  if (!impl_->tokens) return ConsoleUser{"local", Role::operator_, impl_->anonymous_csrf};
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->sessions.find(session_id);
  if (it == impl_->sessions.end()) return std::nullopt;
  // The cookie's Max-Age is the browser's business; the expiry here is ours.
  if (it->second.expires <= impl_->opt.clock()) {
    impl_->sessions.erase(it);
    return std::nullopt;
  }
  return it->second.user;
}

void Console::sign_out(std::string_view session_id) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->sessions.find(session_id);
  if (it != impl_->sessions.end()) impl_->sessions.erase(it);
}

bool Console::csrf_ok(const ConsoleUser& u, std::string_view form_value) {
  return same(u.csrf, form_value);
}

Result<std::string> Console::start_backup(const ConsoleUser& u, const std::string& name) {
  (void)u;  // the service's backups record no operator (a backup writes nothing to a drive)
  return impl_->service.backup_drive(name);
}

Page Console::signin_page(const std::string& message, const std::string& next, int status) const {
  return {status, pages::signin(message, next, impl_->anonymous_csrf)};
}

Page Console::overview(const ConsoleUser& u, const std::string& line,
                       const std::string& status) const {
  const Json drives = impl_->service.drives();
  return {200, pages::overview(u, sign_in_needed(), impl_->service.inventory(), drives, line,
                               status, impl_->opt.clock())};
}

Page Console::position(const ConsoleUser& u, const std::string& name) const {
  const fleet::LineEntry* line = nullptr;
  const fleet::DriveEntry* d = impl_->service.inventory().find_drive(name, &line);
  auto state = impl_->service.drive(name);
  if (!d || !state.ok())
    return error_page(&u, 404, "No such position",
                      "no drive named '" + name + "' in the inventory");
  auto history = impl_->service.history(name);
  return {200,
          pages::position(u, sign_in_needed(), *line, *d, *state, history, impl_->opt.clock())};
}

Page Console::job_page(const ConsoleUser& u, const std::string& id, const std::string& name) const {
  auto j = impl_->service.job(id);
  if (!j.ok()) return error_page(&u, 404, "No such job", j.error().message);
  return {200, pages::job(u, sign_in_needed(), *j, name)};
}

Page Console::error_page(const ConsoleUser* u, int status, const std::string& title,
                         const std::string& message) const {
  return {status, pages::error(u, sign_in_needed(), title, message)};
}

std::string url_encode(std::string_view s) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' ||
        c == '.' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

}  // namespace lmcfg::serve
