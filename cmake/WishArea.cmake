# One static library per area of core/ (core/<area>/*.cpp), so that an area builds and tests on its own.
#   wish_add_area(<area> [GLUE] DEPS <other wish_ areas or targets>...)   GLUE: see wish_speed_up
# creates target wish_<area> with the repository root as include directory (#include "core/<area>/x.hpp").
function(wish_add_area area)
  cmake_parse_arguments(ARG "GLUE" "" "DEPS" ${ARGN})
  set(speed_up_options)
  if(ARG_GLUE)
    set(speed_up_options GLUE)
  endif()
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${area}/*.cpp)
  if(sources)
    add_library(wish_${area} STATIC ${sources})
    target_include_directories(wish_${area} PUBLIC ${WISH_SOURCE_DIR})
    target_link_libraries(wish_${area} PUBLIC ${ARG_DEPS})
    wish_target_warnings(wish_${area})
    wish_speed_up(wish_${area} ${speed_up_options})
  else()
    add_library(wish_${area} INTERFACE)
    target_include_directories(wish_${area} INTERFACE ${WISH_SOURCE_DIR})
    target_link_libraries(wish_${area} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# The COST that makes ctest start the slow tests (Slow*, *Sweep; minutes each) first, the other tests keeping 0:
# without timings of an earlier run (a fresh clone, the CI) ctest -j starts tests in descending COST.
set(WISH_SLOW_TEST_COST 100)

# The tests of an area, tests/<area>/*_test.cpp, linked against LINK, in as few programs as keep the long tests first:
#   * a file holding a Slow*/…Sweep test is its own program <area>_<file> with COST WISH_SLOW_TEST_COST (COST is per
#     program here), so that ctest -j starts its long tests first instead of leaving them to run on alone at the end;
#     with WISH_SLOW_TESTS off, a file whose every test is Slow*/…Sweep gets no program;
#   * every other file of the area goes into one program <area>_tests, compiled in unity batches like the libraries:
#     one GoogleTest main, one link and one test discovery per area instead of per file, and the GoogleTest and Eigen
#     templates the files share instantiated once per batch (issue 28; docs/benchmarks.md, "Compile time").
# ctest's test names are the GoogleTest names (Suite.Test) and the labels are the area's, whichever program holds a
# test, so selections by name or label (-R, -E "Sweep|Slow", -L, -LE slow) are unchanged. A file whose file-local
# names clash with another file of its area sets SKIP_UNITY_BUILD_INCLUSION (tests/CMakeLists.txt); a file with its
# own COMPILE_DEFINITIONS source property is compiled alone by CMake anyway.
function(wish_add_gtests area)
  cmake_parse_arguments(ARG "" "" "LINK;LABELS" ${ARGN})
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${area}/*_test.cpp)
  set(area_sources "")
  foreach(src ${tests})
    file(STRINGS ${src} slow_tests REGEX "^TEST(_F|_P)?\\((Slow|[A-Za-z]*Sweep)")
    file(STRINGS ${src} all_tests REGEX "^TEST(_F|_P)?\\(")
    list(LENGTH slow_tests slow_count)
    list(LENGTH all_tests all_count)
    if(slow_tests AND slow_count EQUAL all_count AND NOT WISH_SLOW_TESTS)
      continue()  # only slow tests, and WISH_SLOW_TESTS is off: no program
    elseif(slow_tests)
      get_filename_component(name ${src} NAME_WE)
      _wish_add_gtest_program(${area}_${name} "${src}" ${WISH_SLOW_TEST_COST} "${area};${ARG_LABELS}" ${ARG_LINK})
    else()
      list(APPEND area_sources ${src})
    endif()
  endforeach()
  if(area_sources)
    _wish_add_gtest_program(${area}_tests "${area_sources}" 0 "${area};${ARG_LABELS}" ${ARG_LINK})
  endif()
endfunction()

function(_wish_add_gtest_program target sources cost labels)
  add_executable(${target} ${sources})
  target_link_libraries(${target} PRIVATE ${ARGN} wish_testing GTest::gtest GTest::gtest_main)
  wish_target_warnings(${target})
  wish_speed_up(${target} TEST)
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${labels}" COST ${cost})
endfunction()
