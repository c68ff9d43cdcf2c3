// SHA-256 against the FIPS 180-4 example vectors, and the tokens file of
// lmcfg serve (only hashes stored, roles, exact messages).
#include <sys/stat.h>

#include <catch2/catch.hpp>

#include "files.hpp"
#include "serve/sha256.hpp"
#include "serve/tokens.hpp"

using namespace lmcfg;

TEST_CASE("serve: SHA-256 gives the FIPS 180-4 example digests (§B.1, §B.2, §B.3)",
          "[serve][tokens]") {
  // FIPS 180-4 / NIST examples: "abc" (one block), the 448-bit message (two
  // blocks), one million 'a'. The empty message is the well-known e3b0c442...
  CHECK(serve::sha256_hex("abc") ==
        "BA7816BF8F01CFEA414140DE5DAE2223B00361A396177A9CB410FF61F20015AD");
  CHECK(serve::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248D6A61D20638B8E5C026930C3E6039A33CE45964FF2167F6ECEDD419DB06C1");
  CHECK(serve::sha256_hex(std::string(1000000, 'a')) ==
        "CDC76E5C9914FB9281A1C7E284D73E67F1809A48A497200E046D39CCC7112CD0");
  CHECK(serve::sha256_hex("") ==
        "E3B0C44298FC1C149AFBF4C8996FB92427AE41E4649B934CA495991B7852B855");
}

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
