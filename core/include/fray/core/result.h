#pragma once
// Recoverable errors are values: Result<T> holds either a T or an Error whose
// message a user can act on ("walk.bvh:212: expected 96 channel values, found 93")
// and whose kind lets a caller react without reading the message (a cancelled
// step is not a failure to report; a stale cache can be rebuilt).
#include <cassert>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace fray {

enum class ErrorKind {
    InvalidInput,  // the input (a file, a spec, an argument) is wrong; the message says where and how
    Io,            // reading or writing failed (missing file, full disk, permissions)
    Stale,         // made by or for something that has changed since (other actions, an older rule)
    Unsupported,   // well formed but not handled by this build (a newer or retired file version)
    Cancelled,     // the user asked to stop (the progress callback returned false)
    Internal,      // a broken invariant: a bug, not the user's input
};

// A short lower-case name of a kind ("invalid input", "cancelled").
inline const char* errorKindName(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::InvalidInput: return "invalid input";
        case ErrorKind::Io: return "I/O";
        case ErrorKind::Stale: return "stale";
        case ErrorKind::Unsupported: return "unsupported";
        case ErrorKind::Cancelled: return "cancelled";
        case ErrorKind::Internal: return "internal";
    }
    return "unknown";
}

struct Error {
    std::string message;
    ErrorKind kind = ErrorKind::InvalidInput;
    bool is(ErrorKind k) const { return kind == k; }
    bool isCancelled() const { return kind == ErrorKind::Cancelled; }
};

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit by design
    Result(Error error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { assert(ok()); return std::get<0>(v_); }
    const T& value() const& { assert(ok()); return std::get<0>(v_); }
    T&& value() && { assert(ok()); return std::get<0>(std::move(v_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { assert(!ok()); return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

// Result<void>: success or an Error.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT
    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    const Error& error() const { assert(!ok_); return error_; }

private:
    Error error_;
    bool ok_ = true;
};

// An error of kind InvalidInput: the default, for the many errors that name
// a bad file, field or argument. Say the kind when it is anything else.
inline Error makeError(std::string message) { return Error{std::move(message), ErrorKind::InvalidInput}; }
inline Error makeError(ErrorKind kind, std::string message) { return Error{std::move(message), kind}; }
// The error a step returns when its progress callback asks it to stop: kind
// Cancelled, message "cancelled" (or "STAGE: cancelled").
inline Error cancelled(std::string_view stage = {}) {
    return Error{stage.empty() ? std::string("cancelled") : std::string(stage) + ": cancelled", ErrorKind::Cancelled};
}

}  // namespace fray
