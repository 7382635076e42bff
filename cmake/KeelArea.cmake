# keel_area(<name> [RECURSE] [DEPENDS <targets>...] [LINK <libs>...] [TEST_DEPENDS <targets>...]
#           [TEST_SPLIT <test files>...])
# RECURSE: sources and tests also in sub-folders of the area (engine/study/ch2/, ...).
# TEST_DEPENDS: libraries only the unit tests link (independent references from a later area, e.g. random graphs
# from keel_sim_impl for the clique tests of pcm).
# TEST_SPLIT: test files whose cases run as a CTest of their own, unit.<name>.<stem> (clique_test.cpp ->
# unit.pcm.clique), so that CTest runs a long file beside the rest of the area's tests instead of after them.
#
# One engine area = one folder engine/<name>/ with
#   *.hpp / *.cpp      ordinary headers and sources that import nothing (DESIGN rule 1) -> library keel_<name>_impl
#   <name>.cppm        the curated facade `export module keel.<name>;` (rule 2)       -> keel_<name> (what consumers link)
#   *_test.cpp         doctest unit tests of internals (include headers, import nothing) -> keel_<name>_tests (CTest)
#
# Consumers (drivers, CLI, benchmarks, facade tests) link keel_<name> and `import keel.<name>;`.
function(keel_area name)
  keel_register_area(${name})
  cmake_parse_arguments(A "RECURSE" "" "DEPENDS;LINK;TEST_DEPENDS;TEST_SPLIT" ${ARGN})
  keel_tiers_check(${name} "${A_DEPENDS}" "${A_TEST_DEPENDS}")
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
  target_include_directories(${impl} ${vis} $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/engine>
                                             $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/keel>)
  keel_unity(${impl})
  target_link_libraries(${impl} ${vis} Eigen3::Eigen ${A_DEPENDS} ${A_LINK})

  add_library(keel_${name} STATIC)
  target_sources(keel_${name} PUBLIC FILE_SET CXX_MODULES BASE_DIRS ${dir} FILES ${dir}/${name}.cppm)
  target_link_libraries(keel_${name} PUBLIC ${impl})
  # The consumer of an installed facade builds its BMI with these features and with the facade's compile options
  # (IMPORTED_CXX_MODULES_COMPILE_OPTIONS): keel's warning flags (and the strict build's -Werror) apply in this tree
  # only, so another compiler's new warning cannot stop a consumer's build.
  target_compile_features(keel_${name} PUBLIC cxx_std_20)
  get_target_property(options keel_${name} COMPILE_OPTIONS)
  if(options)
    list(TRANSFORM options REPLACE "^(.+)$" "$<BUILD_INTERFACE:\\1>")
    set_target_properties(keel_${name} PROPERTIES COMPILE_OPTIONS "${options}")
  endif()
  keel_install_area(${name} "${A_RECURSE}")

  if(KEEL_BUILD_TESTS AND tests)
    keel_doctest_main()
    add_executable(keel_${name}_tests ${tests})
    target_link_libraries(keel_${name}_tests PRIVATE ${impl} ${A_TEST_DEPENDS} keel_doctest_main doctest::doctest)
    target_include_directories(keel_${name}_tests PRIVATE ${CMAKE_SOURCE_DIR}/tests)  # "kit/test_kit.hpp"
    keel_unity(keel_${name}_tests)
    # Test cases that read the benchmark data sets are in the doctest suite "datasets" and fail without the data
    # (tests/kit/dataset_files.hpp). unit.<area> runs the rest; datasets.<area>, label "datasets", runs them. Both
    # leave out the suites of KEEL_UNIT_SKIP_SUITES (Monte-Carlo agreement under the sanitizers: CMakeLists.txt).
    set(skip "")
    set(unit_skip "datasets")
    if(KEEL_UNIT_SKIP_SUITES)
      set(skip "--test-suite-exclude=${KEEL_UNIT_SKIP_SUITES}")
      set(unit_skip "datasets,${KEEL_UNIT_SKIP_SUITES}")
    endif()
    set(split_out "")
    foreach(file ${A_TEST_SPLIT})
      if(NOT EXISTS ${dir}/${file})
        message(FATAL_ERROR "keel_area(${name}): TEST_SPLIT names ${file}, which is not in ${dir}")
      endif()
      string(REGEX REPLACE "_test\\.cpp$" "" stem ${file})
      add_test(NAME unit.${name}.${stem}
               COMMAND keel_${name}_tests --test-suite-exclude=${unit_skip} --source-file=*/${file})
      set_tests_properties(unit.${name}.${stem} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
      list(APPEND split_out "*/${file}")
    endforeach()
    set(rest "")
    if(split_out)
      string(REPLACE ";" "," split_out "${split_out}")
      set(rest "--source-file-exclude=${split_out}")
    endif()
    add_test(NAME unit.${name} COMMAND keel_${name}_tests --test-suite-exclude=${unit_skip} ${rest})
    set_tests_properties(unit.${name} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
    set(dataset_tests FALSE)
    foreach(test ${tests})
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${test})  # a new data-set test reconfigures
      file(STRINGS ${test} hits REGEX "test_suite\\(\"datasets\"\\)|TEST_SUITE\\(\"datasets\"\\)")
      if(hits)
        set(dataset_tests TRUE)
      endif()
    endforeach()
    if(dataset_tests)
      add_test(NAME datasets.${name} COMMAND keel_${name}_tests --test-suite=datasets ${skip})
      set_tests_properties(datasets.${name} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} LABELS datasets)
    endif()
  endif()
endfunction()

# keel_install_area(<name> <recurse>): the areas of the tiers in KEEL_INSTALLED_TIERS and those of
# KEEL_INSTALLED_EXTRA (engine/CMakeLists.txt) go
# into `cmake --install`'s tree and the exported package keel (cmake/keelConfig.cmake.in): the facade keel_<name>
# as keel::<name> with its module interface <name>.cppm (a CMake file set: the consumer's build compiles its own BMI
# from it, since a BMI is tied to the compiler and flags that made it), the library keel_<name>_impl as
# keel::<name>_impl, and the area's headers under include/keel/<name>/ (the facade includes them in its global
# module fragment, so they travel with it).
function(keel_install_area name recurse)
  # The installed names, also as aliases in this tree, so that engine/python links the same names either way.
  add_library(keel::${name} ALIAS keel_${name})
  add_library(keel::${name}_impl ALIAS keel_${name}_impl)
  get_property(tier GLOBAL PROPERTY KEEL_TIER_OF_${name})
  if(NOT tier IN_LIST KEEL_INSTALLED_TIERS AND NOT name IN_LIST KEEL_INSTALLED_EXTRA)
    return()
  endif()
  set_target_properties(keel_${name}_impl PROPERTIES EXPORT_NAME ${name}_impl)
  set_target_properties(keel_${name} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS keel_${name}_impl keel_${name} EXPORT keelTargets COMPONENT development
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          FILE_SET CXX_MODULES DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/keel/modules/${name})
  set(glob GLOB)
  if(recurse)
    set(glob GLOB_RECURSE)
  endif()
  file(${glob} headers RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.hpp)
  foreach(header ${headers})
    get_filename_component(sub ${header} DIRECTORY)
    install(FILES ${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/keel/${name}/${sub} COMPONENT development)
  endforeach()
  set_property(GLOBAL APPEND PROPERTY KEEL_INSTALLED_AREAS ${name})
endfunction()

# keel_unity(<target>): with KEEL_UNITY (CMakeLists.txt), compile the target's sources in batches of
# KEEL_UNITY_BATCH_SIZE, one translation unit each. Only for targets whose sources import no keel module (the areas'
# libraries and unit tests, DESIGN rule 1). A source whose file-scope names clash with another's in its batch is left
# out with SKIP_UNITY_BUILD_INCLUSION in its area's CMakeLists.txt.
function(keel_unity target)
  get_target_property(type ${target} TYPE)
  if(KEEL_UNITY AND NOT type STREQUAL "INTERFACE_LIBRARY")
    # CMake leaves sources it scans for module imports out of unity batches; these import nothing, so no scan.
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${KEEL_UNITY_BATCH_SIZE}
                                               CXX_SCAN_FOR_MODULES OFF)
  endif()
endfunction()

# keel_unity_skip(<source>...): compile these sources of the current area on their own in a unity build. Two sources
# of one batch are one translation unit, so file-scope helpers under the same name (a `fail` or `kPi` in an anonymous
# namespace in both) are redefinitions, and a `using namespace` of one makes the other's names ambiguous.
function(keel_unity_skip)
  set_source_files_properties(${ARGN} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()

# The doctest main, compiled once for every unit-test executable (and the facade-API tests).
function(keel_doctest_main)
  if(NOT TARGET keel_doctest_main)
    add_library(keel_doctest_main STATIC ${CMAKE_SOURCE_DIR}/tests/doctest_main.cpp)
    target_link_libraries(keel_doctest_main PUBLIC doctest::doctest)
  endif()
endfunction()

# Every area registers itself so drivers and benchmarks can link all facades.
function(keel_register_area name)
  set_property(GLOBAL APPEND PROPERTY KEEL_AREAS keel_${name})
endfunction()

# --- Tiers (engine/CMakeLists.txt holds the table; docs/DESIGN.md "Tiers" the rule) ---------------------------------
# keel_tiers_declare() records, for every area of the table, its tier's index and its position in the table.
function(keel_tiers_declare)
  set(index 0)
  set(position 0)
  foreach(tier ${KEEL_TIERS})
    foreach(area ${KEEL_TIER_${tier}})
      set_property(GLOBAL PROPERTY KEEL_TIER_OF_${area} ${tier})
      set_property(GLOBAL PROPERTY KEEL_TIER_INDEX_${area} ${index})
      set_property(GLOBAL PROPERTY KEEL_POSITION_${area} ${position})
      math(EXPR position "${position} + 1")
    endforeach()
    math(EXPR index "${index} + 1")
  endforeach()
  set_property(GLOBAL PROPERTY KEEL_TIERS_DECLARED TRUE)
endfunction()

# The area of a target named keel_<area> or keel_<area>_impl (or keel::<area>, keel::<area>_impl, their aliases);
# empty for anything else (third-party libraries).
function(keel_area_of_target target out)
  set(area "")
  if(target MATCHES "^keel(_|::)([a-z0-9]+)(_impl)?$" AND NOT target STREQUAL "keel::sdpa")
    set(area ${CMAKE_MATCH_2})
  endif()
  set(${out} ${area} PARENT_SCOPE)
endfunction()

# keel_tiers_check(<area> <depends> <test-depends>): a library uses only lower tiers, or areas of its own tier listed
# before it; its unit tests may also link the data tier (generators and manifests as independent references), never
# reproduction, studies or faces unless the area itself is in those tiers.
function(keel_tiers_check area depends test_depends)
  get_property(declared GLOBAL PROPERTY KEEL_TIERS_DECLARED)
  if(NOT declared)
    return()
  endif()
  get_property(tier GLOBAL PROPERTY KEEL_TIER_OF_${area})
  if(NOT tier)
    message(FATAL_ERROR "keel: engine area '${area}' is in no tier: add it to the tier table in "
                        "engine/CMakeLists.txt (docs/DESIGN.md \"Tiers\")")
  endif()
  get_property(index GLOBAL PROPERTY KEEL_TIER_INDEX_${area})
  get_property(position GLOBAL PROPERTY KEEL_POSITION_${area})
  get_property(data_index GLOBAL PROPERTY KEEL_TIER_INDEX_sim)
  foreach(kind library test)
    if(kind STREQUAL "library")
      set(list ${depends})
    else()
      set(list ${test_depends})
    endif()
    foreach(target ${list})
      keel_area_of_target(${target} dep)
      if(NOT dep OR dep STREQUAL area)
        continue()
      endif()
      get_property(dep_tier GLOBAL PROPERTY KEEL_TIER_OF_${dep})
      get_property(dep_index GLOBAL PROPERTY KEEL_TIER_INDEX_${dep})
      get_property(dep_position GLOBAL PROPERTY KEEL_POSITION_${dep})
      set(ok FALSE)
      if(dep_index LESS index OR (dep_index EQUAL index AND dep_position LESS position))
        set(ok TRUE)
      elseif(kind STREQUAL "test" AND NOT dep_index GREATER data_index)
        set(ok TRUE)
      endif()
      if(NOT ok)
        message(FATAL_ERROR "keel: area '${area}' (tier ${tier}) may not ${kind}-depend on ${target}: '${dep}' is "
                            "in tier ${dep_tier}, and a tier uses only the tiers below it (inside a tier, only the "
                            "areas listed before it in engine/CMakeLists.txt; unit tests may also use the data "
                            "tier). See docs/DESIGN.md \"Tiers\".")
      endif()
      set_property(GLOBAL APPEND PROPERTY KEEL_${kind}_DEPS_${area} ${dep})
    endforeach()
  endforeach()
endfunction()

# keel_tiers_write(<file>): the tier table and every area's declared dependencies (for keel_area areas, DEPENDS and
# TEST_DEPENDS; for the cli and python targets, the keel libraries they link), read by tests/tiers/check_tiers.py.
function(keel_tiers_write file)
  set(targets_cli keel)
  set(targets_python keel_python)
  set(json "{\n  \"tiers\": [")
  set(first_tier TRUE)
  foreach(tier ${KEEL_TIERS})
    if(NOT first_tier)
      string(APPEND json ",")
    endif()
    set(first_tier FALSE)
    string(APPEND json "\n    {\"name\": \"${tier}\", \"areas\": [")
    set(first_area TRUE)
    foreach(area ${KEEL_TIER_${tier}})
      if(area STREQUAL "cli" OR area STREQUAL "python")
        set(libs "")
        foreach(t ${targets_${area}})
          if(TARGET ${t})
            get_target_property(l ${t} LINK_LIBRARIES)
            list(APPEND libs ${l})
          endif()
        endforeach()
        foreach(l ${libs})
          keel_area_of_target("${l}" dep)
          if(dep AND NOT dep STREQUAL area)
            set_property(GLOBAL APPEND PROPERTY KEEL_library_DEPS_${area} ${dep})
          endif()
        endforeach()
      endif()
      get_property(lib_deps GLOBAL PROPERTY KEEL_library_DEPS_${area})
      get_property(test_deps GLOBAL PROPERTY KEEL_test_DEPS_${area})
      list(REMOVE_DUPLICATES lib_deps)
      list(REMOVE_DUPLICATES test_deps)
      list(JOIN lib_deps "\", \"" lib_json)
      list(JOIN test_deps "\", \"" test_json)
      if(lib_json)
        set(lib_json "\"${lib_json}\"")
      endif()
      if(test_json)
        set(test_json "\"${test_json}\"")
      endif()
      if(NOT first_area)
        string(APPEND json ",")
      endif()
      set(first_area FALSE)
      string(APPEND json "\n      {\"name\": \"${area}\", \"depends\": [${lib_json}], \"test_depends\": [${test_json}]}")
    endforeach()
    string(APPEND json "]}")
  endforeach()
  string(APPEND json "\n  ]\n}\n")
  file(WRITE ${file} "${json}")
endfunction()
