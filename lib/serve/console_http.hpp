#pragma once
// The console's routes on the HTTP server (docs/console.md "Pages"): GET
// pages, POST forms answered with a redirect (303) so that reloading a page
// never repeats an action. Every page carries the console's
// Content-Security-Policy; the cookie is HttpOnly, SameSite=Strict.
#include "serve/console.hpp"

namespace httplib {
class Server;
}

namespace lmcfg::serve {

inline constexpr const char* kSessionCookie = "lmcfg_session";

void register_console_routes(httplib::Server& server, Console& console);

}  // namespace lmcfg::serve
