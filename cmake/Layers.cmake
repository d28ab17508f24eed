# One library per layer, each with an include directory of its own. The directory
# (build/include/<layer>/) holds only a link named <layer> to the source folder, so
# `#include "gpu/context.h"` resolves for gpu and for every library that links gpu, while a
# layer that includes one above it (gpu including "sim/scene.h") finds no such file: the build
# enforces the layering (tests/layering/check_layers.cmake checks it layer by layer). The layers,
# bottom up: core <- gpu <- grid <- geometry <- sim, render <- control <- session, exports <- study, viewer
# <- runner (`run`'s frame pipeline) <- apps. The shared GLSL/C++ headers (shaders/shared/) come with aquaform_shaders.

function(aquaform_layer_include_dir dir out)
  set(inc ${CMAKE_BINARY_DIR}/include/${dir})
  file(MAKE_DIRECTORY ${inc})
  file(CREATE_LINK ${CMAKE_SOURCE_DIR}/${dir} ${inc}/${dir} SYMBOLIC)
  set(${out} ${inc} PARENT_SCOPE)
endfunction()

# aquaform_layer(target dir sources...): a static library of `sources` whose public include
# directory exposes `dir` (and nothing else of the source tree).
function(aquaform_layer target dir)
  add_library(${target} STATIC ${ARGN})
  aquaform_layer_include_dir(${dir} inc)
  target_include_directories(${target} PUBLIC ${inc})
endfunction()
