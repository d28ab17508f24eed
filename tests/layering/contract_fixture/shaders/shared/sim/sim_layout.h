// sim's contract.
#include "../core/compat.h"
#define SIM_STEPS 4
