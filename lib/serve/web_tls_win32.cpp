// Windows: no TLS library is built for the Windows build (Debian has no
// MinGW-w64 OpenSSL, docs/windows.md), so --tls-cert is refused with the
// reason and what to do instead. Without TLS the service serves loopback
// only (http.cpp check_exposure), which is the technician's-laptop case; a
// plant server that other hosts reach runs the Linux build.
#include "serve/web_tls.hpp"

namespace lmcfg::serve::web {

Result<std::shared_ptr<TlsContext>> TlsContext::load(const std::string& cert,
                                                     const std::string& key) {
  return Error(Errc::invalid_argument,
               "--tls-cert " + cert + " / --tls-key " + key +
                   ": HTTPS is not in the Windows build of lmcfg serve; serve on loopback "
                   "(the default --listen 127.0.0.1:8470), or run the service on Linux for "
                   "other hosts (docs/windows.md)");
}

TlsContext::~TlsContext() = default;

// Never made: load() always fails.
TlsStream::TlsStream(const TlsContext&, int) {}
TlsStream::~TlsStream() = default;
IoStep TlsStream::step(int) const {
  IoStep r;
  r.closed = true;
  r.error = "no TLS in this build";
  return r;
}
IoStep TlsStream::handshake() { return step(0); }
IoStep TlsStream::read(char*, std::size_t) { return step(0); }
IoStep TlsStream::write(const char*, std::size_t) { return step(0); }
bool TlsStream::has_buffered() const { return false; }

}  // namespace lmcfg::serve::web
