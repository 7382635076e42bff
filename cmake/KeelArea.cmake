# keel_area(<name> [RECURSE] [DEPENDS <targets>...] [LINK <libs>...] [TEST_DEPENDS <targets>...])
# RECURSE: sources and tests also in sub-folders of the area (engine/study/ch2/, ...).
# TEST_DEPENDS: libraries only the unit tests link (independent references from a later area, e.g. random graphs
# from keel_sim_impl for the clique tests of pcm).
#
# One engine area = one folder engine/<name>/ with
#   *.hpp / *.cpp      ordinary headers and sources that import nothing (DESIGN rule 1) -> library keel_<name>_impl
#   <name>.cppm        the curated facade `export module keel.<name>;` (rule 2)       -> keel_<name> (what consumers link)
#   *_test.cpp         doctest unit tests of internals (include headers, import nothing) -> keel_<name>_tests (CTest)
#
# Consumers (drivers, CLI, benchmarks, facade tests) link keel_<name> and `import keel.<name>;`.
function(keel_area name)
  keel_register_area(${name})
  cmake_parse_arguments(A "RECURSE" "" "DEPENDS;LINK;TEST_DEPENDS" ${ARGN})
  set(dir ${CMAKE_CURRENT_SOURCE_DIR})
  set(glob GLOB)
  if(A_RECURSE)
    set(glob GLOB_RECURSE)
  endif()
  file(${glob} srcs CONFIGURE_DEPENDS ${dir}/*.cpp)
  file(${glob} tests CONFIGURE_DEPENDS ${dir}/*_test.cpp)
  if(tests)
    list(REMOVE_ITEM srcs ${tests})
  endif()

  set(impl keel_${name}_impl)
  if(srcs)
    add_library(${impl} STATIC ${srcs})
    set(vis PUBLIC)
  else()
    add_library(${impl} INTERFACE)
    set(vis INTERFACE)
  endif()
  target_include_directories(${impl} ${vis} ${CMAKE_SOURCE_DIR}/engine)
  target_link_libraries(${impl} ${vis} Eigen3::Eigen ${A_DEPENDS} ${A_LINK})

  add_library(keel_${name} STATIC)
  target_sources(keel_${name} PUBLIC FILE_SET CXX_MODULES BASE_DIRS ${dir} FILES ${dir}/${name}.cppm)
  target_link_libraries(keel_${name} PUBLIC ${impl})

  if(KEEL_BUILD_TESTS AND tests)
    add_executable(keel_${name}_tests ${tests} ${CMAKE_SOURCE_DIR}/tests/doctest_main.cpp)
    target_link_libraries(keel_${name}_tests PRIVATE ${impl} ${A_TEST_DEPENDS} doctest::doctest)
    target_include_directories(keel_${name}_tests PRIVATE ${CMAKE_SOURCE_DIR}/tests)  # "kit/test_kit.hpp"
    add_test(NAME unit.${name} COMMAND keel_${name}_tests)
    set_tests_properties(unit.${name} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  endif()
endfunction()

# Every area registers itself so drivers and benchmarks can link all facades.
function(keel_register_area name)
  set_property(GLOBAL APPEND PROPERTY KEEL_AREAS keel_${name})
endfunction()
