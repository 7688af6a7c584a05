# cmake --install build --prefix P: headers, libsurfkit.so (SONAME libsurfkit.so.MAJOR.MINOR while
# the version is 0.x) and libsurfkit.a, the surfkit tool, P/lib/pkgconfig/surfkit.pc and the CMake
# package (find_package(surfkit) -> surfkit::surfkit; tests/install builds consumers of both).
include(CMakePackageConfigHelpers)
set(SK_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/surfkit)

set_target_properties(surfkit_shared PROPERTIES EXPORT_NAME surfkit_shared)
set_target_properties(surfkit_static PROPERTIES EXPORT_NAME surfkit_static)
set_target_properties(sk_suitesparse PROPERTIES EXPORT_NAME suitesparse)
install(TARGETS surfkit_shared surfkit_static sk_suitesparse EXPORT surfkitTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS surfkit RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/surfkit DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(EXPORT surfkitTargets NAMESPACE surfkit:: DESTINATION ${SK_CMAKE_DIR})

set(SK_PC_OPENMP "")
if(SK_OPENMP AND OpenMP_C_FOUND)
  foreach(lib ${OpenMP_C_LIB_NAMES})
    string(APPEND SK_PC_OPENMP " -l${lib}")
  endforeach()
endif()
configure_package_config_file(cmake/surfkitConfig.cmake.in
  ${CMAKE_BINARY_DIR}/surfkitConfig.cmake INSTALL_DESTINATION ${SK_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/surfkitConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/surfkitConfig.cmake ${CMAKE_BINARY_DIR}/surfkitConfigVersion.cmake
  DESTINATION ${SK_CMAKE_DIR})

# pkg-config: the private libraries for `pkg-config --static` (SuiteSparse has no .pc on Debian 12)
set(SK_PC_SUITESPARSE "")
foreach(lib cholmod umfpack amd colamd camd ccolamd suitesparseconfig)
  string(APPEND SK_PC_SUITESPARSE " -l${lib}")
endforeach()
# relocatable: the prefix is found from the .pc file's own place (cmake --install --prefix P)
file(RELATIVE_PATH SK_PC_TO_PREFIX ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig
     ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" SK_PC_TO_PREFIX "${SK_PC_TO_PREFIX}")
configure_file(cmake/surfkit.pc.in ${CMAKE_BINARY_DIR}/surfkit.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/surfkit.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
