#include "core/version.h"

namespace aquaform {

std::string aquaform_version() {
#ifdef AQUAFORM_VERSION
    return AQUAFORM_VERSION;
#else
    return "unknown";
#endif
}

}  // namespace aquaform
