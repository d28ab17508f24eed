// render's contract: planted, it includes sim's (render and sim are siblings).
#include "../core/compat.h"
#include "../sim/sim_layout.h"
