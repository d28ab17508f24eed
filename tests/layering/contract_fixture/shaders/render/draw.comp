#version 460
#include "shared/render/view_layout.h"
#include "common/helper.glsl"
