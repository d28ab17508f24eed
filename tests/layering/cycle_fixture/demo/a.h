// Fixture of check_cycles.py: a and b include each other, c is a leaf a includes.
#pragma once
#include "demo/c.h"
