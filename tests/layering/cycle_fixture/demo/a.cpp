#include "demo/a.h"
#include "demo/b.h"
