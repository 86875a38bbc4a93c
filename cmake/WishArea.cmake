# One static library per area of core/ (core/<area>/*.cpp), so that an area builds and tests on its own.
#   wish_add_area(<area> DEPS <other wish_ areas or targets>...)
# creates target wish_<area> with the repository root as include directory (#include "core/<area>/x.hpp").
function(wish_add_area area)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${area}/*.cpp)
  if(sources)
    add_library(wish_${area} STATIC ${sources})
    target_include_directories(wish_${area} PUBLIC ${WISH_SOURCE_DIR})
    target_link_libraries(wish_${area} PUBLIC ${ARG_DEPS})
    wish_target_warnings(wish_${area})
    wish_speed_up(wish_${area})
  else()
    add_library(wish_${area} INTERFACE)
    target_include_directories(wish_${area} INTERFACE ${WISH_SOURCE_DIR})
    target_link_libraries(wish_${area} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# The COST that makes ctest start the slow tests (Slow*, *Sweep; minutes each) first, the other tests keeping 0:
# without timings of an earlier run (a fresh clone, the CI) ctest -j starts tests in descending COST.
set(WISH_SLOW_TEST_COST 100)

# Every tests/<area>/*_test.cpp becomes its own GoogleTest executable linked against LINK.
function(wish_add_gtests area)
  cmake_parse_arguments(ARG "" "" "LINK;LABELS" ${ARGN})
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${area}/*_test.cpp)
  foreach(src ${tests})
    get_filename_component(name ${src} NAME_WE)
    set(target ${area}_${name})
    add_executable(${target} ${src})
    target_link_libraries(${target} PRIVATE ${ARG_LINK} wish_testing GTest::gtest GTest::gtest_main)
    wish_target_warnings(${target})
    wish_speed_up(${target} TEST)
    # A program holding a Slow*/…Sweep test starts first (all its tests: COST is per program here), so that the
    # long tests do not run on alone at the end of a parallel ctest.
    file(STRINGS ${src} slow_tests REGEX "^TEST(_F|_P)?\\((Slow|[A-Za-z]*Sweep)")
    set(cost 0)
    if(slow_tests)
      set(cost ${WISH_SLOW_TEST_COST})
    endif()
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${area};${ARG_LABELS}" COST ${cost})
  endforeach()
endfunction()
