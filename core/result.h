// A value or an error message: loaders return this instead of throwing, so that callers decide
// how to report (the CLI prints and exits non-zero; tests assert on the message).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace aquaform {

struct Error {
    std::string message;
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

private:
    std::variant<T, Error> data_;
};

}  // namespace aquaform
