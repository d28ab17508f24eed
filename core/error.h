// The one error policy: functions that users reach through a file or a flag return Result<T>
// (core/result.h) with a message that names the problem and the fix; code inside the libraries
// throws Failure, and the command's top level (apps/cli.cpp) prints it and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace aquaform {

class Failure : public std::runtime_error {
public:
    enum class Kind {
        input,     ///< a value the caller gave is out of range or inconsistent
        resource,  ///< the device or the host lacks something (memory, a driver, a limit)
        internal,  ///< aquaform itself broke a rule (a bug: a mismatch between C++ and a shader, say)
    };
    explicit Failure(const std::string& message, Kind kind = Kind::input) : std::runtime_error(message), kind_(kind) {}
    Kind kind() const { return kind_; }

private:
    Kind kind_;
};

inline Failure resource_failure(const std::string& message) { return Failure(message, Failure::Kind::resource); }
inline Failure internal_failure(const std::string& message) { return Failure(message, Failure::Kind::internal); }

}  // namespace aquaform
