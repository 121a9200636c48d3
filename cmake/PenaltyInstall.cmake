# install/export so that find_package(penalty) and target_link_libraries(... penalty::core) work.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

get_property(_penalty_targets GLOBAL PROPERTY PENALTY_INSTALL_TARGETS)
set_target_properties(penalty_core PROPERTIES EXPORT_NAME core)
install(TARGETS ${_penalty_targets} EXPORT penaltyTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/penalty DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT penaltyTargets NAMESPACE penalty:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/penalty)

configure_package_config_file(cmake/penaltyConfig.cmake.in
  ${PROJECT_BINARY_DIR}/penaltyConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/penalty)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/penaltyConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/penaltyConfig.cmake ${PROJECT_BINARY_DIR}/penaltyConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/penalty)
