#include "demo/b.h"
#include "a.h"
