#include "serve/console.hpp"

#include <algorithm>
#include <deque>
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
  struct Nonce {
    TimePoint expires;
    std::string addr;  // the client address it was issued to
  };
  std::mutex mu;
  std::map<std::string, Session, std::less<>> sessions;
  std::map<std::string, Nonce, std::less<>> signin_nonces;  // value -> expiry, address
  // The plans made here, until executed (the service checks their expiry;
  // the oldest go beyond kPlansKept).
  static constexpr std::size_t kPlansKept = 64;
  std::map<std::string, Json> plans;
  std::deque<std::string> plan_order;

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

namespace {

// The key in `m` to drop to make room, the one that goes first (`first`: a
// comparison of two entries) among those of the owner (`owner_of(entry)`)
// holding the most entries: whoever fills the pool pushes out their own
// entries, never the few of another.
template <class Map, class Owner, class First>
typename Map::iterator console_room(Map& m, Owner owner_of, First first) {
  std::map<std::string, std::size_t, std::less<>> held;
  for (auto& kv : m) ++held[owner_of(kv.second)];
  auto best = m.end();
  std::size_t best_n = 0;
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::size_t n = held[owner_of(it->second)];
    if (best == m.end() || n > best_n || (n == best_n && first(it->second, best->second))) {
      best = it;
      best_n = n;
    }
  }
  return best;
}

// The key in `m` of `owner`'s entry that goes first; m.end() when it has none.
template <class Map, class Owner, class First>
typename Map::iterator console_own_first(Map& m, const std::string& owner, Owner owner_of,
                                         First first) {
  auto best = m.end();
  for (auto it = m.begin(); it != m.end(); ++it)
    if (owner_of(it->second) == owner && (best == m.end() || first(it->second, best->second)))
      best = it;
  return best;
}

}  // namespace

Result<std::string> Console::signin_nonce(std::string_view current, const std::string& addr) {
  LMCFG_ASSIGN_OR_RETURN(std::string v, random_hex(32));
  const TimePoint now = impl_->opt.clock();
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto& n = impl_->signin_nonces;
  for (auto it = n.begin(); it != n.end();)
    it = it->second.expires <= now ? n.erase(it) : std::next(it);
  if (auto it = n.find(current); !current.empty() && it != n.end()) return it->first;
  const auto addr_of = [](const Impl::Nonce& x) -> const std::string& { return x.addr; };
  const auto first = [](const Impl::Nonce& a, const Impl::Nonce& b) {
    return a.expires < b.expires;
  };
  // One address's values push out only its own; the pool, the most held.
  const auto mine = static_cast<std::size_t>(
      std::count_if(n.begin(), n.end(), [&](auto& kv) { return kv.second.addr == addr; }));
  if (mine >= kSigninNoncesPerAddress) n.erase(console_own_first(n, addr, addr_of, first));
  while (n.size() >= kSigninNonces) n.erase(console_room(n, addr_of, first));
  n[v] = {now + std::chrono::minutes(10), addr};
  return v;
}

bool Console::signin_nonce_ok(std::string_view cookie_value, std::string_view form_value) {
  if (!same(cookie_value, form_value)) return false;
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->signin_nonces.find(form_value);
  if (it == impl_->signin_nonces.end()) return false;
  const bool fresh = it->second.expires > impl_->opt.clock();
  impl_->signin_nonces.erase(it);
  return fresh;
}

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
  // Bounds per token and in all: a token's sign-ins beyond its bound end its
  // own session that expires first; the pool makes room from the token that
  // holds the most, so no one's sign-ins push out another person's session.
  auto& ss = impl_->sessions;
  const auto who_of = [](const Impl::Session& x) -> const std::string& { return x.user.who; };
  const auto first = [](const Impl::Session& a, const Impl::Session& b) {
    return a.expires < b.expires;
  };
  const auto mine = static_cast<std::size_t>(
      std::count_if(ss.begin(), ss.end(), [&](auto& kv) { return kv.second.user.who == e->name; }));
  if (mine >= kMaxSessionsPerToken) ss.erase(console_own_first(ss, e->name, who_of, first));
  while (ss.size() >= kMaxSessions) ss.erase(console_room(ss, who_of, first));
  ss[s.id] = {s.user, now + impl_->opt.session_ttl};
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
  return impl_->service.backup_drive(name, u.who);
}

Result<std::string> Console::make_plan(const ConsoleUser& u, const std::string& name,
                                       const std::string& rev) {
  LMCFG_ASSIGN_OR_RETURN(Json plan, impl_->service.plan(name, rev, u.who));
  const std::string id = plan["plan_id"].get<std::string>();
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->plans[id] = std::move(plan);
  impl_->plan_order.push_back(id);
  while (impl_->plan_order.size() > Impl::kPlansKept) {
    impl_->plans.erase(impl_->plan_order.front());
    impl_->plan_order.pop_front();
  }
  return id;
}

Result<std::string> Console::approve(const ConsoleUser& u, const std::string& name,
                                     const std::string& rev, const std::string& reason,
                                     const std::string& ticket) {
  LMCFG_ASSIGN_OR_RETURN(Json a, impl_->service.approve(name, {rev, u.who, reason, ticket}));
  return a["job"].is_string() ? a["job"].get<std::string>() : std::string();
}

Result<std::string> Console::start_restore(const ConsoleUser& u, const std::string& plan_id,
                                           const std::string& reason, const std::string& ticket,
                                           bool skip_incompatible) {
  Service::ExecuteRequest req;
  req.plan_id = plan_id;
  req.audit = {u.who, reason, ticket};
  req.skip_incompatible = skip_incompatible;
  auto id = impl_->service.execute(req);
  if (id.ok()) {
    // The plan's page, reopened (Back), says it ran instead of offering the write again.
    std::lock_guard<std::mutex> lock(impl_->mu);
    if (auto it = impl_->plans.find(plan_id); it != impl_->plans.end())
      it->second["executed_job"] = *id;
  }
  return id;
}

Page Console::replace_page(const ConsoleUser& u, const std::string& name,
                           const std::string& rev) const {
  const fleet::LineEntry* line = nullptr;
  const fleet::DriveEntry* d = impl_->service.inventory().find_drive(name, &line);
  if (!d)
    return error_page(&u, 404, "No such position",
                      "no drive named '" + name + "' in the inventory");
  auto history = impl_->service.history(name);
  // The approved configuration is what a restore puts back unless someone
  // chooses another revision.
  std::string approved;
  if (auto st = impl_->service.drive(name); st.ok() && (*st)["approved"].is_object())
    approved = (*st)["approved"].value("rev", "");
  return {200, pages::replace(u, sign_in_needed(), *line, *d, rev, approved, history)};
}

Page Console::plan_page(const ConsoleUser& u, const std::string& plan_id) const {
  Json plan;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    auto it = impl_->plans.find(plan_id);
    if (it == impl_->plans.end())
      return error_page(&u, 404, "No such plan",
                        "no plan '" + plan_id +
                            "' (executed already, or made too long ago): "
                            "plan again from the position's page");
    plan = it->second;
  }
  return {200, pages::plan(u, sign_in_needed(), plan, impl_->opt.clock())};
}

Result<std::string> Console::report(const std::string& name, const std::string& rev) const {
  return impl_->service.report_html(name, rev);
}

Result<std::string> Console::diff(const std::string& name, const std::string& from,
                                  const std::string& to) const {
  return impl_->service.diff_html(name, from, to);
}

Page Console::failure_page(const ConsoleUser& u, const std::string& title, const Error& e,
                           const RetryForm& retry, const std::string& position) const {
  int status = 500;
  if (e.code == Errc::not_found) status = 404;
  if (e.code == Errc::invalid_argument) status = 400;
  if (e.code == Errc::plan_refused) status = 409;
  if (e.code == Errc::interrupted || line_busy(e)) status = 503;
  // The drive or the link failed, not this server.
  for (Errc link :
       {Errc::timeout, Errc::link_closed, Errc::io_error, Errc::drive_refused, Errc::frame_short,
        Errc::frame_malformed, Errc::checksum_mismatch, Errc::unexpected_response})
    if (e.code == link) status = 502;
  if (class_of(e.code) == ErrorClass::drive_refusal) status = 502;
  return {status, pages::failure(&u, sign_in_needed(), title, words::help_for(e, position),
                                 e.message, retry, position)};
}

Result<void> Console::cancel_retry(const ConsoleUser& u, const std::string& name) {
  LMCFG_TRY(impl_->service.cancel_retry(name, u.who));
  return {};
}

Page Console::signin_page(const std::string& message, const std::string& next,
                          const std::string& csrf, int status) const {
  return {status, pages::signin(message, next, csrf)};
}

Page Console::overview(const ConsoleUser& u, const std::string& line, const std::string& status,
                       const std::string& page) const {
  // Digits only, at most 6 of them: anything else is the first page.
  std::size_t n = 1;
  if (!page.empty() && page.size() <= 6 &&
      page.find_first_not_of("0123456789") == std::string::npos)
    n = std::max<std::size_t>(1, std::stoul(page));
  // Every position's status for the counts and the filter; the whole state
  // only of the rows shown (a page of kOverviewRows).
  const Json drives = impl_->service.drive_summaries();
  auto row = [this](const Json& summary) {
    auto whole = impl_->service.drive(summary["name"].get<std::string>());
    return whole.ok() ? *whole : summary;
  };
  return {200, pages::overview(u, sign_in_needed(), impl_->service.inventory(), drives, line,
                               status, impl_->opt.clock(), n, row)};
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
  if (!j.ok()) {
    // A job of an earlier run, or one no longer kept, is not "no such job".
    const bool never = j.error().message.rfind("no job ", 0) == 0;
    return error_page(&u, 404, never ? "No such job" : "Job no longer kept", j.error().message);
  }
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
