# Installation: one library, libcolibri, shared and static, made of the module libraries; the
# public headers under include/colibri (umbrella include/colibri/colibri.h); the `colibri`
# command; a pkg-config file and a CMake package (find_package(colibri)).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(COLIBRI_MODULES colibri_brep colibri_ssi colibri_boolean colibri_io colibri_models)

set(_colibri_archives)
foreach(m ${COLIBRI_MODULES})
  get_target_property(_type ${m} TYPE)
  if(_type STREQUAL "STATIC_LIBRARY")
    list(APPEND _colibri_archives ${m})
  endif()
endforeach()

# Shared: every object of the module archives (whole archives), their dependencies linked in
# through the modules' own usage requirements.
set(_whole)
foreach(m ${_colibri_archives})
  list(APPEND _whole $<TARGET_FILE:${m}>)
endforeach()
# cb_version() is the package's own object, in both libraries.
add_library(colibri_version_obj OBJECT ${PROJECT_SOURCE_DIR}/cmake/colibri_version.c)
target_compile_definitions(colibri_version_obj PRIVATE COLIBRI_VERSION="${PROJECT_VERSION}")
target_link_libraries(colibri_version_obj PRIVATE colibri_warnings)
add_library(colibri_shared SHARED $<TARGET_OBJECTS:colibri_version_obj>)
add_dependencies(colibri_shared ${_colibri_archives})
target_link_libraries(colibri_shared PRIVATE
  -Wl,--whole-archive ${_whole} -Wl,--no-whole-archive ${COLIBRI_MODULES})
set_target_properties(colibri_shared PROPERTIES
  OUTPUT_NAME colibri VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}
  LINKER_LANGUAGE CXX)

# Static: the module archives merged into one (ar's MRI script), so a user links one -lcolibri.
set(_colibri_ar_script ${CMAKE_CURRENT_BINARY_DIR}/libcolibri.mri)
set(_colibri_static ${CMAKE_CURRENT_BINARY_DIR}/static/libcolibri.a)
set(_mri "create ${_colibri_static}\n")
foreach(m ${_colibri_archives})
  string(APPEND _mri "addlib $<TARGET_FILE:${m}>\n")
endforeach()
string(APPEND _mri "addmod $<TARGET_OBJECTS:colibri_version_obj>\nsave\nend\n")
file(GENERATE OUTPUT ${_colibri_ar_script} CONTENT "${_mri}")
add_custom_command(OUTPUT ${_colibri_static}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/static
  COMMAND ${CMAKE_COMMAND} -E remove -f ${_colibri_static}
  COMMAND ${CMAKE_AR} -M < ${_colibri_ar_script}
  DEPENDS ${_colibri_archives} colibri_version_obj ${_colibri_ar_script}
  COMMENT "Merging the module archives into libcolibri.a" VERBATIM)
add_custom_target(colibri_static ALL DEPENDS ${_colibri_static})

# Public headers: every module header but the internal ones and the C++ adapters' own.
foreach(dir brep ssi io boolean models)
  file(GLOB _headers ${PROJECT_SOURCE_DIR}/${dir}/*.h)
  list(FILTER _headers EXCLUDE REGEX "(_internal|_cgal|_openmesh)\\.h$")
  install(FILES ${_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/colibri/${dir})
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/include/colibri/colibri.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/colibri)

install(TARGETS colibri_shared colibri
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${_colibri_static} DESTINATION ${CMAKE_INSTALL_LIBDIR})

# What a static link needs besides libcolibri.a (the shared library carries these itself).
set(COLIBRI_STATIC_LIBS "-lOpenMeshCore -ltbb -lflint-arb -lflint -lmpfr -lgmp -lstdc++ -lm")
file(RELATIVE_PATH COLIBRI_PC_TO_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig
  ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" COLIBRI_PC_TO_PREFIX "${COLIBRI_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/colibri.pc.in ${CMAKE_CURRENT_BINARY_DIR}/colibri.pc
  @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/colibri.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/colibriConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/colibriConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/colibri
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_LIBDIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/colibriConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/colibriConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/colibriConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/colibri)
