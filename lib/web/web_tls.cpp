#include "web/web_tls.hpp"

#include <openssl/err.h>
#include <openssl/ssl.h>

namespace lmcfg::web {

namespace {
SSL* ssl_of(void* p) { return static_cast<SSL*>(p); }

// TLS 1.2's suites with an ephemeral key exchange and an AEAD cipher
// (RFC 7525 §4.2 recommends exactly these families); TLS 1.3's suites are
// all forward-secret AEAD and are left at OpenSSL's list.
constexpr const char* kTls12Suites =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:"
    "ECDHE-ECDSA-AES256-GCM-SHA384:ECDHE-RSA-AES256-GCM-SHA384:"
    "ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305";

std::string openssl_error() {
  const unsigned long e = ERR_get_error();
  if (!e) return "";
  char buf[256];
  ERR_error_string_n(e, buf, sizeof buf);
  ERR_clear_error();
  return buf;
}
}  // namespace

Result<std::shared_ptr<TlsContext>> TlsContext::load(const std::string& cert,
                                                     const std::string& key) {
  std::shared_ptr<TlsContext> c(new TlsContext());
  SSL_CTX* ctx = SSL_CTX_new(TLS_server_method());
  c->ctx_ = ctx;
  const Error bad(Errc::file_error, "--tls-cert " + cert + " / --tls-key " + key +
                                        ": cannot load them as a PEM certificate and its "
                                        "private key (readable files, the key matching the "
                                        "certificate)");
  if (!ctx) return bad;
  SSL_CTX_set_min_proto_version(ctx, TLS1_2_VERSION);
  SSL_CTX_set_options(ctx, SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION |
                               SSL_OP_CIPHER_SERVER_PREFERENCE | SSL_OP_NO_TICKET);
  SSL_CTX_set_mode(ctx, SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER);
  if (SSL_CTX_set_cipher_list(ctx, kTls12Suites) != 1) return bad;
  if (SSL_CTX_use_certificate_chain_file(ctx, cert.c_str()) != 1 ||
      SSL_CTX_use_PrivateKey_file(ctx, key.c_str(), SSL_FILETYPE_PEM) != 1 ||
      SSL_CTX_check_private_key(ctx) != 1) {
    ERR_clear_error();
    return bad;
  }
  return c;
}

TlsContext::~TlsContext() { SSL_CTX_free(static_cast<SSL_CTX*>(ctx_)); }

TlsStream::TlsStream(const TlsContext& ctx, int fd) {
  SSL* s = SSL_new(static_cast<SSL_CTX*>(ctx.native()));
  if (s && SSL_set_fd(s, fd) == 1) {
    SSL_set_accept_state(s);
    ssl_ = s;
  } else {
    SSL_free(s);
  }
}

TlsStream::~TlsStream() { SSL_free(ssl_of(ssl_)); }

IoStep TlsStream::step(int rc) const {
  IoStep r;
  if (rc > 0) {
    r.n = static_cast<std::size_t>(rc);
    return r;
  }
  switch (SSL_get_error(ssl_of(ssl_), rc)) {
    case SSL_ERROR_WANT_READ:
      r.want_read = true;
      break;
    case SSL_ERROR_WANT_WRITE:
      r.want_write = true;
      break;
    case SSL_ERROR_ZERO_RETURN:
      r.closed = true;
      break;
    default:
      r.closed = true;
      r.error = openssl_error();
      if (r.error.empty()) r.error = "TLS connection failed";
  }
  return r;
}

IoStep TlsStream::handshake() {
  const int rc = SSL_do_handshake(ssl_of(ssl_));
  if (rc != 1) return step(rc);
  IoStep done;
  done.n = 1;
  return done;
}

IoStep TlsStream::read(char* buf, std::size_t size) {
  return step(SSL_read(ssl_of(ssl_), buf, static_cast<int>(size)));
}

IoStep TlsStream::write(const char* buf, std::size_t size) {
  return step(SSL_write(ssl_of(ssl_), buf, static_cast<int>(size)));
}

bool TlsStream::has_buffered() const { return SSL_pending(ssl_of(ssl_)) > 0; }

}  // namespace lmcfg::web
