# SPDX-License-Identifier: Apache-2.0
# `cmake --install <build> [--prefix P]`: the public headers, the shared library, a CMake package
# (find_package(dynblur) → imported target dynblur::dynblur) and a pkg-config file (dynblur.pc).
# Included by the top-level CMakeLists.txt after modules/dynblur defined opencv_dynblur; not used
# inside an OpenCV build tree (ocv_create_module installs the module there) nor for the Python
# extension, which links the library statically (DYNBLUR_LIBRARY_TYPE STATIC).
#
#   P/include/opencv2/dynblur.hpp, P/include/opencv2/dynblur/*.hpp
#   P/lib/libopencv_dynblur.so.<major.minor.patch>, .so.<major.minor> (the soname), .so
#   P/lib/cmake/dynblur/dynblurConfig.cmake, dynblurConfigVersion.cmake, dynblurTargets*.cmake
#   P/lib/pkgconfig/dynblur.pc
#
# The consumer sees OpenCV only: SUNDIALS, FFTW, ViSP, libmodbus and Eigen are private to the
# shared library (its DT_NEEDED entries), so neither the exported target nor dynblur.pc names them.
# tests/install/ is an application built against the installed tree (scripts/install_check.sh).

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(_dynblur_module_dir ${PROJECT_SOURCE_DIR}/modules/dynblur)
set(_dynblur_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/dynblur)

# Before 1.0 a minor version may change the ABI, so the soname carries major.minor.
set_target_properties(opencv_dynblur PROPERTIES
  VERSION ${PROJECT_VERSION}
  SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
  EXPORT_NAME dynblur)
# The headers' folder in the prefix; OpenCV's own include path comes with its imported targets.
target_include_directories(opencv_dynblur PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)

install(DIRECTORY ${_dynblur_module_dir}/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
install(TARGETS opencv_dynblur EXPORT dynblurTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT dynblurTargets NAMESPACE dynblur:: DESTINATION ${_dynblur_cmake_dir})

# The OpenCV modules the consumer's find_dependency asks for: those the library links publicly.
set(DYNBLUR_OPENCV_COMPONENTS ${DYNBLUR_OPENCV_LIBS})
list(TRANSFORM DYNBLUR_OPENCV_COMPONENTS REPLACE "^opencv_" "")
list(JOIN DYNBLUR_OPENCV_COMPONENTS " " DYNBLUR_OPENCV_COMPONENTS)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/dynblurConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cmake/dynblurConfig.cmake INSTALL_DESTINATION ${_dynblur_cmake_dir})
# 0.x: only the same minor version promises the same API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/dynblurConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/dynblurConfig.cmake
              ${PROJECT_BINARY_DIR}/cmake/dynblurConfigVersion.cmake
        DESTINATION ${_dynblur_cmake_dir})

# dynblur.pc finds its prefix from its own place (${pcfiledir}), so `--prefix P` at install time
# needs no reconfiguration.
file(RELATIVE_PATH DYNBLUR_PC_PREFIX_FROM_PCFILEDIR
     /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" DYNBLUR_PC_PREFIX_FROM_PCFILEDIR "${DYNBLUR_PC_PREFIX_FROM_PCFILEDIR}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/dynblur.pc.in ${PROJECT_BINARY_DIR}/pkgconfig/dynblur.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/dynblur.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
