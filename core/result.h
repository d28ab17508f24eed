// A value or an error message: loaders return this instead of throwing, so that callers decide
// how to report (the CLI prints and exits non-zero; tests assert on the message).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace aquaform {

struct Error {
    /// What the exit status says: bad input the user can fix in what they gave (exit 2), or the
    /// machine stopped the work (a full disk, a lost device: exit 1).
    enum class Kind { input, resource };
    std::string message;
    Kind kind = Kind::input;
};

template <typename T>
class Result {
public:
    Result(T value) : data_(std::move(value)) {}
    Result(Error error) : data_(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(data_); }
    explicit operator bool() const { return ok(); }
    const T& value() const& { return std::get<T>(data_); }
    T& value() & { return std::get<T>(data_); }
    T&& value() && { return std::get<T>(std::move(data_)); }
    const std::string& error() const { return std::get<Error>(data_).message; }
    /// The error as it is, to pass on with its kind.
    const Error& failure() const { return std::get<Error>(data_); }
    bool failed_for_resources() const { return !ok() && failure().kind == Error::Kind::resource; }

private:
    std::variant<T, Error> data_;
};

}  // namespace aquaform
