# FindKeelSdpa — the SDPA 7 semidefinite solver as Debian ships it (libsdpa-dev), as the imported target keel::sdpa.
#
# Use: find_package(KeelSdpa REQUIRED) (or include(FindKeelSdpa)); cmake/ is on CMAKE_MODULE_PATH. Then link
# keel::sdpa.
#
# Debian's SDPA is a static library (/usr/lib/libsdpa.a) that calls MUMPS (dmumps_c, the sequential build that
# libsdpa-dev depends on), LAPACK, BLAS and pthreads; its header sdpa_call.h includes dmumps_c.h. The shared
# libdmumps_seq brings the rest of MUMPS (mumps_common_seq, pord_seq, mpiseq_seq, scotch, gfortran) by itself.
# Sets KEEL_SDPA_INCLUDE_DIR, KEEL_SDPA_LIBRARY and KeelSdpa_FOUND; stops with an error naming the package when a
# piece is missing.
if(TARGET keel::sdpa)
  set(KeelSdpa_FOUND TRUE)
  return()
endif()

find_path(KEEL_SDPA_INCLUDE_DIR sdpa_call.h)
find_path(KEEL_SDPA_MUMPS_INCLUDE_DIR dmumps_c.h)
find_library(KEEL_SDPA_LIBRARY NAMES sdpa)
find_library(KEEL_SDPA_DMUMPS_LIBRARY NAMES dmumps_seq)
find_package(LAPACK QUIET)  # also finds BLAS; LAPACK_LIBRARIES holds both
find_package(Threads REQUIRED)

set(_keel_sdpa_missing "")
foreach(_v KEEL_SDPA_INCLUDE_DIR KEEL_SDPA_MUMPS_INCLUDE_DIR KEEL_SDPA_LIBRARY KEEL_SDPA_DMUMPS_LIBRARY)
  if(NOT ${_v})
    list(APPEND _keel_sdpa_missing ${_v})
  endif()
endforeach()
if(NOT LAPACK_FOUND)
  list(APPEND _keel_sdpa_missing LAPACK)
endif()
if(_keel_sdpa_missing)
  message(FATAL_ERROR "SDPA (the SDP solver of keel.sos) not found: ${_keel_sdpa_missing}. On Debian install "
                      "libsdpa-dev (it brings libmumps-seq-dev and OpenBLAS): run scripts/setup, or "
                      "apt-get install libsdpa-dev.")
endif()

# GLOBAL: the target is created in one area's directory and reaches every consumer of that area.
add_library(keel::sdpa INTERFACE IMPORTED GLOBAL)
set_target_properties(keel::sdpa PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${KEEL_SDPA_INCLUDE_DIR};${KEEL_SDPA_MUMPS_INCLUDE_DIR}"
  INTERFACE_LINK_LIBRARIES "${KEEL_SDPA_LIBRARY};${KEEL_SDPA_DMUMPS_LIBRARY};${LAPACK_LIBRARIES};Threads::Threads")
set(KeelSdpa_FOUND TRUE)
mark_as_advanced(KEEL_SDPA_INCLUDE_DIR KEEL_SDPA_MUMPS_INCLUDE_DIR KEEL_SDPA_LIBRARY KEEL_SDPA_DMUMPS_LIBRARY)
unset(_keel_sdpa_missing)
