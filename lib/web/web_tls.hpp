#pragma once
// TLS for lmcfg serve's HTTP server (OpenSSL): the server context with the
// protocol and cipher policy of docs/serve.md "Security model", and one
// connection's non-blocking handshake, reads and writes for the event loop.
#include <memory>
#include <string>

#include "common/result.hpp"
#include "web/web_socket.hpp"

namespace lmcfg::web {

class TlsContext {
 public:
  // The PEM certificate (chain) and its private key. TLS 1.2 with forward-
  // secret AEAD suites only (ECDHE with AES-GCM or ChaCha20-Poly1305), TLS
  // 1.3 (all its suites are both) preferred, no compression, no
  // renegotiation. Errc::file_error naming both files when they do not load
  // or do not belong together.
  static Result<std::shared_ptr<TlsContext>> load(const std::string& cert, const std::string& key);
  ~TlsContext();
  TlsContext(const TlsContext&) = delete;
  TlsContext& operator=(const TlsContext&) = delete;
  void* native() const { return ctx_; }  // SSL_CTX*

 private:
  TlsContext() = default;
  void* ctx_ = nullptr;
};

// One accepted socket's TLS session (the socket stays the caller's to close).
class TlsStream {
 public:
  TlsStream(const TlsContext& ctx, int fd);
  ~TlsStream();
  TlsStream(const TlsStream&) = delete;
  TlsStream& operator=(const TlsStream&) = delete;
  bool valid() const { return ssl_ != nullptr; }
  IoStep handshake();  // n == 1 once complete
  IoStep read(char* buf, std::size_t size);
  IoStep write(const char* buf, std::size_t size);
  bool has_buffered() const;  // decrypted bytes waiting (poll would not see them)

 private:
  IoStep step(int rc) const;
  void* ssl_ = nullptr;
};

}  // namespace lmcfg::web
