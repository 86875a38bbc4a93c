# Compile time (issue 28; the measurements are in docs/benchmarks.md, "Compile time"). Most of a translation unit's
# cost here is the headers every file includes (Eigen through core/mesh/mesh.hpp, nlohmann/json, the standard
# library; GoogleTest in the tests) and the Eigen templates each file instantiates again. Two measures, both
# switchable (the generated code is the same: a precompiled header only saves parsing, a unity batch only
# concatenates .cpp files):
#   WISH_PCH    the heavy headers are precompiled once per build (wish_pch for the libraries and programs,
#               wish_test_pch adding GoogleTest for the test programs) and every target reuses that one file
#               (REUSE_FROM), instead of each translation unit parsing them again;
#   WISH_UNITY  the libraries are compiled in batches of WISH_UNITY_BATCH .cpp files, so that a batch parses
#               its headers and emits its shared Eigen instantiations once. A source that must stay alone sets
#               SKIP_UNITY_BUILD_INCLUSION (e.g. server/http_server.cpp: httplib.h must not meet Eigen).
option(WISH_PCH "Precompile the heavy third-party headers once and reuse them in every target" ON)
option(WISH_UNITY "Compile the libraries in unity batches (faster from scratch, slower to rebuild one file)" ON)
# 0: one batch per target (scripts/serve.sh's one-off build of the service; a file-local name may then be defined
# once per library only, which the files of core/ keep to).
set(WISH_UNITY_BATCH 8 CACHE STRING "Source files per unity batch (0: the whole target in one batch)")

# The precompiled header must be built with exactly the flags of the files that use it (the compiler ignores it
# otherwise, with a -Winvalid-pch warning): every WISH target links OpenMP (through wish_common), is C++20 and
# takes the warning flags of wish_target_warnings, so the PCH targets do the same.
set(WISH_PCH_HEADERS
  <algorithm> <array> <cmath> <cstddef> <cstdint> <functional> <map> <memory> <optional> <set> <span>
  <stdexcept> <string> <string_view> <unordered_map> <utility> <vector>
  <Eigen/Core> <Eigen/Geometry> <Eigen/SparseCore>
  <nlohmann/json.hpp>)

# The service's glue (HTTP, JSON wire format, command-line parsing, the pipeline's orchestration: targets passed to
# wish_speed_up with GLUE) is compiled at WISH_GLUE_OPTIMIZATION in Release builds instead of -O3: its run time is
# a few milliseconds of a request's hundreds (the numerical areas keep -O3), while -O3 is about a third of its
# compile time (docs/benchmarks.md, "Third pass: the service's glue at -O1, one eigensolver"). GCC records a function's
# optimisation level where the function is parsed, so the Eigen, JSON and standard-library templates of a header
# precompiled at -O3 stay -O3 in a file compiled at -O1: the glue has its own precompiled header, wish_glue_pch.
set(WISH_GLUE_OPTIMIZATION "-O1" CACHE STRING "Optimisation of the service's glue code in Release builds")
set(WISH_GLUE_COMPILE_OPTIONS $<$<CONFIG:Release>:${WISH_GLUE_OPTIMIZATION}>)
set(WISH_LINK_MAP_DIR ${CMAKE_BINARY_DIR}/link-maps)  # the glue executables' link maps (wish_speed_up)
file(MAKE_DIRECTORY ${WISH_LINK_MAP_DIR})

if(WISH_PCH)
  file(WRITE ${CMAKE_BINARY_DIR}/wish_pch.cpp "// The translation unit that builds the shared precompiled header.\n")
  add_library(wish_pch STATIC ${CMAKE_BINARY_DIR}/wish_pch.cpp)
  target_link_libraries(wish_pch PRIVATE Eigen3::Eigen OpenMP::OpenMP_CXX nlohmann_json::nlohmann_json)
  target_precompile_headers(wish_pch PRIVATE ${WISH_PCH_HEADERS})
  wish_target_warnings(wish_pch)
  add_library(wish_glue_pch STATIC ${CMAKE_BINARY_DIR}/wish_pch.cpp)
  target_link_libraries(wish_glue_pch PRIVATE Eigen3::Eigen OpenMP::OpenMP_CXX nlohmann_json::nlohmann_json)
  target_precompile_headers(wish_glue_pch PRIVATE ${WISH_PCH_HEADERS})
  target_compile_options(wish_glue_pch PRIVATE ${WISH_GLUE_COMPILE_OPTIONS})
  wish_target_warnings(wish_glue_pch)
  if(WISH_BUILD_TESTS)
    add_library(wish_test_pch STATIC ${CMAKE_BINARY_DIR}/wish_pch.cpp)
    target_link_libraries(wish_test_pch PRIVATE Eigen3::Eigen OpenMP::OpenMP_CXX nlohmann_json::nlohmann_json
                                                GTest::gtest)
    target_precompile_headers(wish_test_pch PRIVATE ${WISH_PCH_HEADERS} <gtest/gtest.h>)
    wish_target_warnings(wish_test_pch)
  endif()
endif()

# Called by wish_add_area, wish_add_gtests and the other CMakeLists for each of their targets.
#   wish_speed_up(<target> [TEST] [GLUE])   TEST: a test program (its precompiled header includes GoogleTest);
#                                           GLUE: the service's glue, compiled at WISH_GLUE_OPTIMIZATION (above)
function(wish_speed_up target)
  cmake_parse_arguments(ARG "TEST;GLUE" "" "" ${ARGN})
  if(ARG_GLUE)
    target_compile_options(${target} PRIVATE ${WISH_GLUE_COMPILE_OPTIONS})
    set_property(GLOBAL APPEND PROPERTY WISH_GLUE_TARGETS ${target})
    # The link map of a glue executable in Release builds (GNU ld): tests/cmake/check_glue_link_map.py reads it to
    # show that no numerical template function is taken from the glue's -O1 objects (the linker keeps the first copy
    # of a template it meets, and the glue's objects come first on the link line).
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "EXECUTABLE" AND CMAKE_BUILD_TYPE STREQUAL "Release" AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_link_options(${target} PRIVATE "LINKER:-Map=${WISH_LINK_MAP_DIR}/${target}.map")
      set_property(GLOBAL APPEND PROPERTY WISH_GLUE_LINK_MAPS ${target})
    endif()
  endif()
  if(WISH_PCH)
    if(ARG_TEST AND TARGET wish_test_pch)
      target_precompile_headers(${target} REUSE_FROM wish_test_pch)
    elseif(ARG_GLUE)
      target_precompile_headers(${target} REUSE_FROM wish_glue_pch)
    else()
      target_precompile_headers(${target} REUSE_FROM wish_pch)
    endif()
  endif()
  if(WISH_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${WISH_UNITY_BATCH})
  endif()
endfunction()
