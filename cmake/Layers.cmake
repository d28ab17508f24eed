# One library per layer, each with an include directory of its own. The directory
# (build/include/<layer>/) holds only a link named <layer> to the source folder, so
# `#include "gpu/context.h"` resolves for gpu and for every library that links gpu, while a
# layer that includes one it does not link (gpu including "sim/scene.h") finds no such file: the
# build enforces the layering (tests/layering/check_layers.cmake checks it layer by layer). Each
# layer links exactly the layers its files include (CMakeLists.txt). The layers, bottom up, each
# with what it links:
#   core
#   pictures (core)                      gpu (core)
#   grid (gpu)                           geometry (core)
#   sim (grid, geometry, pictures)       render (grid, pictures)
#   control (sim)
#   session (control, render)            exports (sim, render)
#   bench (session)   viewer (session)   runner (session, exports)
#   study (bench)
#   apps (everything)
# (a layer listed with the nearest layers it links; it links the lower ones it includes too).
# The shared GLSL/C++ headers (shaders/shared/) come with aquaform_shaders, in one folder per layer
# (core, solids, particles, grid, sim, render, control); a layer includes only its own folder's and
# those of the layers below it (tests/layering/check_shader_contracts.py checks it).

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
