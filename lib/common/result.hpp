#pragma once
// Error handling inside the library: a std::error_code plus a message that
// says what went wrong, where, and what was expected. Exceptions are used only
// at the edges (tools).
#include <cassert>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <variant>

namespace lmcfg {

// Library-wide error conditions. Values are stable: tools map them to exit codes.
enum class Errc {
  ok = 0,
  // communication (link)
  timeout = 1,
  link_closed,
  io_error,
  // telegram (codec)
  frame_short,
  frame_overlong,
  frame_malformed,
  checksum_mismatch,
  unexpected_response,
  // drive answered with an error communication state (see CommStateCategory)
  drive_refused,
  // input and files
  invalid_argument,
  parse_error,
  unsupported_version,
  validation_failed,
  not_found,
  file_error,
  // operations
  plan_refused,
  verify_mismatch,
  cancelled,
  not_supported,  // the link or drive cannot do what was asked (e.g. change a TCP gateway's baud
                  // rate)
  interrupted,    // SIGINT/SIGTERM: stopped between two telegrams (ClientOptions::cancel)
};

const std::error_category& lmcfg_category() noexcept;
std::error_code make_error_code(Errc e) noexcept;

// Communication state bytes of LinRS §16.1 (C1..C9) as their own category,
// so a drive refusal carries the exact state code it answered.
const std::error_category& comm_state_category() noexcept;
std::error_code make_comm_state_error(unsigned state_byte) noexcept;
// The text of an error communication state a manual names (LinRS §16.1; D7h
// from LinRS 3V27 p32), or nullptr for a state no source names.
const char* comm_state_text(unsigned state_byte) noexcept;

// What an error means for the caller, whatever its code: the one
// classification of lmcfg errors. An error_code compares equal to each class it
// belongs to (`e.code == ErrorClass::link_failure`), through the category's
// equivalent(); the classes of every Errc and of the communication states are
// listed in result.cpp (class_of) and checked by tests/common/test_result.cpp.
// The tools' exit codes follow the classes (tools/lmcfg/link_options.cpp).
enum class ErrorClass {
  // The link failed (exit code 4): bad_answer or link_down.
  link_failure = 1,
  // An answer lost, garbled or not the one expected (timeout, frame_*,
  // checksum_mismatch, unexpected_response): repeating a read may help, and
  // the client does.
  bad_answer,
  // The link itself failed (link_closed, io_error, and any error code from
  // outside lmcfg's categories): repeating does not help.
  link_down,
  // The drive answered with an error communication state (C1..C9, any byte of
  // comm_state_category()) or Errc::drive_refused (exit code 5).
  drive_refusal,
  // Bad file, option or argument; something the link or drive cannot do
  // (exit code 2).
  bad_input,
  plan_refused,     // exit code 3
  verify_mismatch,  // exit code 6
  interrupted,      // SIGINT/SIGTERM (exit code 130)
};

const std::error_category& error_class_category() noexcept;
std::error_condition make_error_condition(ErrorClass c) noexcept;
// The class of an error code: bad_answer or link_down for a link failure
// (never link_failure itself), link_down for codes of categories other than
// lmcfg's and the communication states; nullopt for Errc::ok and values outside
// Errc.
std::optional<ErrorClass> class_of(const std::error_code& code) noexcept;

struct Error {
  std::error_code code;
  std::string message;

  Error() = default;
  Error(std::error_code c, std::string m) : code(c), message(std::move(m)) {}
  Error(Errc e, std::string m) : code(make_error_code(e)), message(std::move(m)) {}
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(Error e) : v_(std::move(e)) {}      // NOLINT(google-explicit-constructor)

  bool ok() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const Error& error() const& {
    assert(!ok());
    return std::get<1>(v_);
  }
  Error&& error() && {
    assert(!ok());
    return std::get<1>(std::move(v_));
  }

 private:
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error e) : err_(std::move(e)), failed_(true) {}  // NOLINT(google-explicit-constructor)
  bool ok() const noexcept { return !failed_; }
  explicit operator bool() const noexcept { return ok(); }
  const Error& error() const& {
    assert(failed_);
    return err_;
  }
  Error&& error() && {
    assert(failed_);
    return std::move(err_);
  }

 private:
  Error err_;
  bool failed_ = false;
};

// A drive's refusal (C1..C9, comm_state_category) as an unknown, anything else
// (link failures) as the error: for optional questions such as a parameter's
// type or default, which a drive may not answer for every UPID.
template <class T>
Result<std::optional<T>> unless_refused(Result<T> r) {
  if (r.ok()) return std::optional<T>(std::move(r).value());
  if (r.error().code == ErrorClass::drive_refusal) return std::optional<T>();
  return std::move(r).error();
}

}  // namespace lmcfg

namespace std {
template <>
struct is_error_code_enum<lmcfg::Errc> : true_type {};
template <>
struct is_error_condition_enum<lmcfg::ErrorClass> : true_type {};
}  // namespace std

// Propagate an error from an expression returning Result<...>.
#define LMCFG_TRY(expr)                                             \
  do {                                                              \
    auto lmcfg_try_r_ = (expr);                                     \
    if (!lmcfg_try_r_.ok()) return std::move(lmcfg_try_r_).error(); \
  } while (0)

#define LMCFG_CONCAT_INNER_(a, b) a##b
#define LMCFG_CONCAT_(a, b) LMCFG_CONCAT_INNER_(a, b)
#define LMCFG_ASSIGN_OR_RETURN_IMPL_(tmp, lhs, expr) \
  auto tmp = (expr);                                 \
  if (!tmp.ok()) return std::move(tmp).error();      \
  lhs = std::move(tmp).value()
// LMCFG_ASSIGN_OR_RETURN(auto x, f()); declares x from a successful Result.
#define LMCFG_ASSIGN_OR_RETURN(lhs, expr) \
  LMCFG_ASSIGN_OR_RETURN_IMPL_(LMCFG_CONCAT_(lmcfg_aor_, __LINE__), lhs, expr)
