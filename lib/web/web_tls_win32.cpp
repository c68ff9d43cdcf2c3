// TLS for lmcfg serve in the Windows build: Mbed TLS 2.28, built from
// Debian's source package by scripts/build-windows.sh (Debian builds no
// OpenSSL for MinGW-w64). The policy is web_tls.cpp's where Mbed TLS has it:
// TLS 1.2 with the same forward-secret AEAD suites (ECDHE with AES-GCM or
// ChaCha20-Poly1305, RFC 7525 §4.2), no renegotiation, no session tickets,
// no compression (none is built in). TLS 1.3 is not offered: 2.28's TLS 1.3
// is client-only and experimental (docs/windows.md).
#include <mbedtls/ctr_drbg.h>
#include <mbedtls/entropy.h>
#include <mbedtls/error.h>
#include <mbedtls/net_sockets.h>
#include <mbedtls/pk.h>
#include <mbedtls/ssl.h>
#include <mbedtls/ssl_ciphersuites.h>
#include <mbedtls/x509_crt.h>

#include "web/web_tls.hpp"

namespace lmcfg::web {

namespace {

const int kSuites[] = {
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_GCM_SHA256,
    MBEDTLS_TLS_ECDHE_RSA_WITH_AES_128_GCM_SHA256,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_GCM_SHA384,
    MBEDTLS_TLS_ECDHE_RSA_WITH_AES_256_GCM_SHA384,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_CHACHA20_POLY1305_SHA256,
    MBEDTLS_TLS_ECDHE_RSA_WITH_CHACHA20_POLY1305_SHA256,
    0,
};

// The configuration and what it points to; one per TlsContext.
struct Config {
  mbedtls_ssl_config conf;
  mbedtls_entropy_context entropy;
  mbedtls_ctr_drbg_context drbg;
  mbedtls_x509_crt cert;
  mbedtls_pk_context key;
  Config() {
    mbedtls_ssl_config_init(&conf);
    mbedtls_entropy_init(&entropy);
    mbedtls_ctr_drbg_init(&drbg);
    mbedtls_x509_crt_init(&cert);
    mbedtls_pk_init(&key);
  }
  ~Config() {
    mbedtls_ssl_config_free(&conf);
    mbedtls_pk_free(&key);
    mbedtls_x509_crt_free(&cert);
    mbedtls_ctr_drbg_free(&drbg);
    mbedtls_entropy_free(&entropy);
  }
  Config(const Config&) = delete;
  Config& operator=(const Config&) = delete;
};

// One connection: its session and the socket its records go over.
struct Session {
  mbedtls_ssl_context ssl;
  int socket;
  explicit Session(int fd) : socket(fd) { mbedtls_ssl_init(&ssl); }
  ~Session() { mbedtls_ssl_free(&ssl); }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

Session* session_of(void* p) { return static_cast<Session*>(p); }

// The records go over web_socket's non-blocking reads and writes (the event
// loop waits); their outcome in Mbed TLS's terms.
int send_cb(void* ctx, const unsigned char* buf, size_t len) {
  const IoStep r =
      send_some(static_cast<Session*>(ctx)->socket, reinterpret_cast<const char*>(buf), len);
  if (r.n > 0) return static_cast<int>(r.n);
  return r.closed ? MBEDTLS_ERR_NET_SEND_FAILED : MBEDTLS_ERR_SSL_WANT_WRITE;
}

int recv_cb(void* ctx, unsigned char* buf, size_t len) {
  const IoStep r = recv_some(static_cast<Session*>(ctx)->socket, reinterpret_cast<char*>(buf), len);
  if (r.n > 0) return static_cast<int>(r.n);
  if (r.want_read) return MBEDTLS_ERR_SSL_WANT_READ;
  return r.error.empty() ? 0 : MBEDTLS_ERR_NET_RECV_FAILED;  // 0: the peer closed
}

std::string mbedtls_text(int rc) {
  char buf[200] = "";
  mbedtls_strerror(rc, buf, sizeof buf);
  return buf;
}

}  // namespace

Result<std::shared_ptr<TlsContext>> TlsContext::load(const std::string& cert,
                                                     const std::string& key) {
  std::shared_ptr<TlsContext> c(new TlsContext());
  auto* cfg = new Config();
  c->ctx_ = cfg;
  const Error bad(Errc::file_error, "--tls-cert " + cert + " / --tls-key " + key +
                                        ": cannot load them as a PEM certificate and its "
                                        "private key (readable files, the key matching the "
                                        "certificate)");
  static const char kPersonal[] = "lmcfg serve";
  if (mbedtls_ctr_drbg_seed(&cfg->drbg, mbedtls_entropy_func, &cfg->entropy,
                            reinterpret_cast<const unsigned char*>(kPersonal),
                            sizeof kPersonal - 1) != 0)
    return Error(Errc::io_error, "TLS: the random generator could not be seeded");
  if (mbedtls_ssl_config_defaults(&cfg->conf, MBEDTLS_SSL_IS_SERVER, MBEDTLS_SSL_TRANSPORT_STREAM,
                                  MBEDTLS_SSL_PRESET_DEFAULT) != 0)
    return bad;
  mbedtls_ssl_conf_rng(&cfg->conf, mbedtls_ctr_drbg_random, &cfg->drbg);
  mbedtls_ssl_conf_min_version(&cfg->conf, MBEDTLS_SSL_MAJOR_VERSION_3,
                               MBEDTLS_SSL_MINOR_VERSION_3);
  mbedtls_ssl_conf_ciphersuites(&cfg->conf, kSuites);
  mbedtls_ssl_conf_renegotiation(&cfg->conf, MBEDTLS_SSL_RENEGOTIATION_DISABLED);
  // Any certificate that did not parse fails the whole chain (a positive count).
  if (mbedtls_x509_crt_parse_file(&cfg->cert, cert.c_str()) != 0 ||
      mbedtls_pk_parse_keyfile(&cfg->key, key.c_str(), nullptr) != 0 ||
      mbedtls_pk_check_pair(&cfg->cert.pk, &cfg->key) != 0 ||
      mbedtls_ssl_conf_own_cert(&cfg->conf, &cfg->cert, &cfg->key) != 0)
    return bad;
  return c;
}

TlsContext::~TlsContext() { delete static_cast<Config*>(ctx_); }

TlsStream::TlsStream(const TlsContext& ctx, int fd) {
  auto* s = new Session(fd);
  if (mbedtls_ssl_setup(&s->ssl, &static_cast<Config*>(ctx.native())->conf) != 0) {
    delete s;
    return;
  }
  mbedtls_ssl_set_bio(&s->ssl, s, send_cb, recv_cb, nullptr);
  ssl_ = s;
}

TlsStream::~TlsStream() { delete session_of(ssl_); }

IoStep TlsStream::step(int rc) const {
  IoStep r;
  if (rc > 0) {
    r.n = static_cast<std::size_t>(rc);
    return r;
  }
  switch (rc) {
    case MBEDTLS_ERR_SSL_WANT_READ:
      r.want_read = true;
      break;
    case MBEDTLS_ERR_SSL_WANT_WRITE:
      r.want_write = true;
      break;
    case 0:  // the peer closed the socket
    case MBEDTLS_ERR_SSL_PEER_CLOSE_NOTIFY:
      r.closed = true;
      break;
    default:
      r.closed = true;
      r.error = mbedtls_text(rc);
      if (r.error.empty()) r.error = "TLS connection failed";
  }
  return r;
}

IoStep TlsStream::handshake() {
  const int rc = mbedtls_ssl_handshake(&session_of(ssl_)->ssl);
  if (rc != 0) return step(rc);
  IoStep done;
  done.n = 1;
  return done;
}

IoStep TlsStream::read(char* buf, std::size_t size) {
  return step(
      mbedtls_ssl_read(&session_of(ssl_)->ssl, reinterpret_cast<unsigned char*>(buf), size));
}

IoStep TlsStream::write(const char* buf, std::size_t size) {
  return step(
      mbedtls_ssl_write(&session_of(ssl_)->ssl, reinterpret_cast<const unsigned char*>(buf), size));
}

bool TlsStream::has_buffered() const {
  return mbedtls_ssl_get_bytes_avail(&session_of(ssl_)->ssl) > 0;
}

}  // namespace lmcfg::web
