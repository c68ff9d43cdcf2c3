// The tokens file of lmcfg serve (only hashes stored, roles, exact
// messages); SHA-256 itself is tested in test_sha256.cpp.
#include <sys/stat.h>

#include <catch2/catch.hpp>

#include "files.hpp"
#include "serve/sha256.hpp"
#include "serve/tokens.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_tokens {

using namespace lmcfg;

TEST_CASE("serve: token add stores only the hash, tokens are found by role", "[serve][tokens]") {
  test::ScratchDir d("serve-tokens");
  const std::string file = (d.path / "tokens").string();
  auto viewer = serve::add_token(file, "grafana", serve::Role::viewer);
  auto op = serve::add_token(file, "ops", serve::Role::operator_);
  REQUIRE(viewer.ok());
  REQUIRE(op.ok());
  CHECK(viewer->size() == 64);
  CHECK(*viewer != *op);
  const std::string text = test::slurp(file);
  CHECK(text.find(*viewer) == std::string::npos);
  CHECK(text == "grafana viewer " + serve::sha256_hex(*viewer) + "\nops operator " +
                    serve::sha256_hex(*op) + "\n");
  struct stat st {};
  REQUIRE(::stat(file.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0600);
  auto tokens = serve::load_tokens(file);
  REQUIRE(tokens.ok());
  REQUIRE(serve::find_token(*tokens, *viewer));
  CHECK(serve::find_token(*tokens, *viewer)->name == "grafana");
  CHECK(serve::find_token(*tokens, *op)->role == serve::Role::operator_);
  CHECK_FALSE(serve::find_token(*tokens, "not-a-token"));

  auto again = serve::add_token(file, "ops", serve::Role::viewer);
  REQUIRE_FALSE(again.ok());
  CHECK(again.error().message == file + ": a token named 'ops' exists already");
  auto blank = serve::add_token(file, "a b", serve::Role::viewer);
  REQUIRE_FALSE(blank.ok());
  CHECK(blank.error().message == "token name 'a b' must be one word without blanks or '#'");
  CHECK(serve::parse_role("admin").error().message ==
        "role 'admin' is not one of viewer, operator");

  test::spit(file, text + "broken line\n");
  auto bad = serve::load_tokens(file);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        file + ":3: expected NAME ROLE SHA256 (written by lmcfg serve token add)");
}

TEST_CASE("serve: a tokens file others may write is refused with the fix, names are text",
          "[serve][tokens]") {
  test::ScratchDir d("serve-tokens-mode");
  const std::string file = (d.path / "tokens").string();
  REQUIRE(serve::add_token(file, "ops", serve::Role::operator_).ok());
  REQUIRE(::chmod(file.c_str(), 0620) == 0);
  auto group = serve::load_tokens(file);
  REQUIRE_FALSE(group.ok());
  CHECK(group.error().code == Errc::file_error);
  CHECK(group.error().message ==
        file +
            ": the tokens file is writable by its group (mode 0620), so anyone there could "
            "add a token: run chmod 600 " +
            file);
  REQUIRE(::chmod(file.c_str(), 0646) == 0);
  CHECK(serve::load_tokens(file).error().message ==
        file +
            ": the tokens file is writable by others (mode 0646), so anyone there could add "
            "a token: run chmod 600 " +
            file);
  // token add appends to it only once it is fixed.
  CHECK_FALSE(serve::add_token(file, "two", serve::Role::viewer).ok());
  REQUIRE(::chmod(file.c_str(), 0640) == 0);  // group may read: not a way in
  CHECK(serve::load_tokens(file).ok());

  CHECK(serve::add_token(file, "ops\xFF", serve::Role::viewer).error().message ==
        "token name is not valid UTF-8 (byte 0xFF at offset 3): send UTF-8 text");
  REQUIRE(::chmod(file.c_str(), 0600) == 0);
  test::spit(file, test::slurp(file) + "o\x01ps viewer " + std::string(64, 'a') + "\n");
  CHECK(serve::load_tokens(file).error().message ==
        file +
            ":2: token name contains a control character (0x01 at offset 1): give one line "
            "without control characters");
}

}  // namespace serve_test_tokens
