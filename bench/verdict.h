// One benchmark target's verdict, as every benchmark prints and records it.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace aquaform::study {

/// One target's verdict for the terminal (a line) and the JSON (its figures, status and pass).
struct Verdict {
    nlohmann::json json;
    std::string line;
};

}  // namespace aquaform::study
