# Checks that the build enforces the layering (cmake/Layers.cmake): every layer's own sources,
# preprocessed with their real flags (compile_commands.json), can include a header of each layer
# it links (directly or through another layer) and cannot find one of any other layer.
# Usage: cmake -DBUILD_DIR=... -DSOURCE_DIR=... -P check_layers.cmake
cmake_minimum_required(VERSION 3.25)

# layer | a header of it | the layers it may include, comma-separated (besides itself): those it
# links in CMakeLists.txt and theirs
set(layers
  "core|core/result.h|"
  "pictures|pictures/image_io.h|core"
  "gpu|gpu/context.h|core"
  "grid|grid/neighbor_grid.h|core,gpu"
  "geometry|geometry/mesh.h|core"
  "sim|sim/scene.h|core,gpu,grid,geometry,pictures"
  "render|render/surface_frame.h|core,gpu,grid,pictures"
  "control|control/placement.h|core,gpu,grid,geometry,pictures,sim"
  "session|session/simulation_session.h|core,gpu,grid,geometry,pictures,sim,render,control"
  "exports|exports/mesh_export.h|core,gpu,grid,geometry,pictures,sim,render"
  "bench|bench/bench_sim.h|core,gpu,grid,geometry,pictures,sim,render,control,session"
  "study|study/study_spec.h|core,gpu,grid,geometry,pictures,sim,render,control,session,bench"
  "viewer|viewer/view_worker.h|core,gpu,grid,geometry,pictures,sim,render,control,session"
  "runner|runner/run_files.h|core,gpu,grid,geometry,pictures,sim,render,control,session,exports"
  "apps|apps/cli.h|core,gpu,grid,geometry,pictures,sim,render,control,session,exports,bench,study,viewer,runner")

file(READ ${BUILD_DIR}/compile_commands.json db)
string(JSON count LENGTH "${db}")
math(EXPR last "${count} - 1")

set(failures "")
set(probes 0)
foreach(entry ${layers})
  string(REPLACE "|" ";" fields "${entry}")
  list(GET fields 0 layer)
  list(LENGTH fields n)
  set(allowed "")
  if(n GREATER 2)
    list(GET fields 2 allowed)
    string(REPLACE "," ";" allowed "${allowed}")
  endif()
  # The compile command of one source file of this layer.
  set(command "")
  foreach(i RANGE ${last})
    string(JSON file GET "${db}" ${i} file)
    if(file MATCHES "^${SOURCE_DIR}/${layer}/[^/]+\\.cpp$")
      string(JSON command GET "${db}" ${i} command)
      string(JSON directory GET "${db}" ${i} directory)
      break()
    endif()
  endforeach()
  if(command STREQUAL "")
    string(APPEND failures "no source of layer ${layer} in compile_commands.json\n")
    continue()
  endif()
  separate_arguments(args UNIX_COMMAND "${command}")
  # Drop the output and the source; the probe stands in the layer's folder so that its quoted
  # includes search there first, as the layer's own files do.
  set(flags "")
  set(skip FALSE)
  foreach(a ${args})
    if(skip)
      set(skip FALSE)
    elseif(a STREQUAL "-o" OR a STREQUAL "-c")
      set(skip TRUE)
    else()
      list(APPEND flags "${a}")
    endif()
  endforeach()
  foreach(other ${layers})
    string(REPLACE "|" ";" ofields "${other}")
    list(GET ofields 0 target_layer)
    list(GET ofields 1 header)
    list(FIND allowed ${target_layer} found)
    if(target_layer STREQUAL layer OR found GREATER -1)
      set(expect_ok TRUE)
    else()
      set(expect_ok FALSE)
    endif()
    set(probe ${BUILD_DIR}/layer_probes/${layer}/probe_${target_layer}.cpp)
    file(WRITE ${probe} "#include \"${header}\"\n")
    execute_process(COMMAND ${flags} -E ${probe} WORKING_DIRECTORY ${directory}
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)  # preprocessing finds every include
    math(EXPR probes "${probes} + 1")
    if(expect_ok AND NOT rc EQUAL 0)
      string(APPEND failures "${layer} cannot include ${header}, which it may:\n${err}\n")
    elseif(NOT expect_ok AND rc EQUAL 0)
      string(APPEND failures "${layer} can include ${header} of a layer above it; its include directories must not reach ${target_layer}/\n")
    endif()
  endforeach()
endforeach()

if(failures)
  message(FATAL_ERROR "layering is not enforced:\n${failures}")
endif()
message(STATUS "layering enforced: ${probes} includes probed")
