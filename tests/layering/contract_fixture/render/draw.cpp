// Planted: render including sim's contract.
#include "shaders/shared/sim/sim_layout.h"
