#pragma once
// The console's routes on the HTTP server (docs/console.md "Pages"): GET
// pages, POST forms answered with a redirect (303) so that reloading a page
// never repeats an action. Every page carries the console's
// Content-Security-Policy; the cookies are HttpOnly, SameSite=Strict, and
// Secure over HTTPS.
#include "serve/console.hpp"

namespace lmcfg::web {
class Router;
}

namespace lmcfg::serve {

inline constexpr const char* kSessionCookie = "lmcfg_session";
// The sign-in form's CSRF value, as a cookie of /signin only.
inline constexpr const char* kSigninCookie = "lmcfg_signin";

void register_console_routes(web::Router& router, Console& console);

}  // namespace lmcfg::serve
