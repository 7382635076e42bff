# The exported CMake package keel, written by `cmake --install` (after engine/ has declared its areas):
#   <prefix>/lib/libkeel_<area>.a, libkeel_<area>_impl.a      the installed areas' libraries (KEEL_INSTALLED_TIERS)
#   <prefix>/lib/cmake/keel/modules/<area>/<area>.cppm         their module interfaces (file sets)
#   <prefix>/include/keel/<area>/*.hpp                         their headers
#   <prefix>/lib/cmake/keel/keelConfig.cmake, ...Version.cmake, keelTargets*.cmake, FindKeelSdpa.cmake
#   <prefix>/bin/keel                                          the keel command (engine/cli)
# so that another project's find_package(keel) and target_link_libraries(x PRIVATE keel::pgo) work
# (examples/consumer, built against an installed tree by the CTest install.consumer). The version is the project's
# (CMakeLists.txt), the one `keel --version` and keel.__version__ print.
include(CMakePackageConfigHelpers)
set(KEEL_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/keel)
get_property(KEEL_INSTALLED_AREAS GLOBAL PROPERTY KEEL_INSTALLED_AREAS)
list(JOIN KEEL_INSTALLED_AREAS " " KEEL_INSTALLED_AREAS_LIST)
if(CMAKE_POSITION_INDEPENDENT_CODE)
  set(KEEL_PIC TRUE)
else()
  set(KEEL_PIC FALSE)
endif()
install(EXPORT keelTargets NAMESPACE keel:: DESTINATION ${KEEL_PACKAGE_DIR} CXX_MODULES_DIRECTORY modules
        COMPONENT development)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/keelConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/package/keelConfig.cmake INSTALL_DESTINATION ${KEEL_PACKAGE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/keelConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/keelConfig.cmake ${CMAKE_BINARY_DIR}/package/keelConfigVersion.cmake
              ${CMAKE_SOURCE_DIR}/cmake/FindKeelSdpa.cmake
        DESTINATION ${KEEL_PACKAGE_DIR} COMPONENT development)
