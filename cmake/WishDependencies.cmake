# All third-party code comes from Debian 12 packages (scripts/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(nlohmann_json 3 REQUIRED)
find_package(spdlog REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
find_package(ZLIB REQUIRED)
find_package(TIFF 4.5 REQUIRED)
# OpenMesh: Debian's libopenmesh-dev when installed, else its files as scripts/install-deps.sh unpacks them for the
# service alone (the package's dependency on libopenscenegraph-dev is 153 packages WISH does not use).
find_package(OpenMesh QUIET)
if(NOT OpenMesh_FOUND)
  file(GLOB WISH_UNPACKED_OPENMESH "${CMAKE_CURRENT_SOURCE_DIR}/build/debian-dev/libopenmesh-dev/usr/lib/*/cmake/OpenMesh")
  find_package(OpenMesh PATHS ${WISH_UNPACKED_OPENMESH} NO_DEFAULT_PATH)
  if(NOT OpenMesh_FOUND)
    message(FATAL_ERROR "OpenMesh not found: run scripts/install-deps.sh (it installs libopenmesh1 and unpacks "
                        "libopenmesh-dev's headers into build/debian-dev/), or apt-get install libopenmesh-dev")
  endif()
endif()

# SuiteSparse 5.x on Debian 12 ships no CMake package: find CHOLMOD by hand.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(wish::cholmod INTERFACE IMPORTED)
target_include_directories(wish::cholmod INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(wish::cholmod INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

# libsvm 3.24: header in /usr/include/libsvm.
find_path(LIBSVM_INCLUDE_DIR svm.h PATH_SUFFIXES libsvm REQUIRED)
find_library(LIBSVM_LIBRARY svm REQUIRED)
add_library(wish::libsvm INTERFACE IMPORTED)
target_include_directories(wish::libsvm INTERFACE ${LIBSVM_INCLUDE_DIR})
target_link_libraries(wish::libsvm INTERFACE ${LIBSVM_LIBRARY})

# OME-Zarr label images: zip stores (libzip) and the chunk compressors zstd and blosc (zlib is above).
pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
pkg_check_modules(BLOSC REQUIRED IMPORTED_TARGET blosc)
# The per-object table of a classified label volume as AnnData (.h5ad): Debian's serial libhdf5 (C API).
pkg_check_modules(HDF5 REQUIRED IMPORTED_TARGET hdf5)

# cpp-httplib 0.11 is a compiled library with only a pkg-config file.
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)

if(WISH_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(WISH_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
