# penalty_add_layer(<name> FOLDER <folder> DEPENDS <targets...>)
# One library per pipeline stage, from include/penalty/<folder>/*.hpp and src/<folder>/*.cpp, with
# the stage's vector kernels of src/kernels/<folder>/*.cpp (the one place of the intrinsics, lane
# layouts and prefetches: src/kernels/).
# A layer without .cpp files is an INTERFACE (header-only) target. Sources are globbed with
# CONFIGURE_DEPENDS so that adding a file needs no CMake edit.
function(penalty_add_layer name)
  cmake_parse_arguments(L "" "FOLDER" "DEPENDS" ${ARGN})
  file(GLOB_RECURSE _srcs CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/src/${L_FOLDER}/*.cpp"
       "${PROJECT_SOURCE_DIR}/src/kernels/${L_FOLDER}/*.cpp")
  set(_target penalty_${name})
  if(_srcs)
    add_library(${_target} STATIC ${_srcs})
    target_include_directories(${_target} PUBLIC
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
      PRIVATE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(${_target} PUBLIC ${L_DEPENDS} PRIVATE $<BUILD_INTERFACE:penalty_warnings>)
    target_compile_features(${_target} PUBLIC cxx_std_20)
    # A few sources to a translation unit (PENALTY_UNITY_LIBRARY): the headers, Eigen's above all,
    # are parsed once a batch instead of once a file.
    set_target_properties(${_target} PROPERTIES UNITY_BUILD ${PENALTY_UNITY_LIBRARY}
                                                UNITY_BUILD_BATCH_SIZE ${PENALTY_UNITY_BATCH_SIZE})
    if(PENALTY_FUZZ)  # libFuzzer's coverage of the library's code (cmake/PenaltyWarnings.cmake)
      target_compile_options(${_target} PRIVATE -fsanitize=fuzzer-no-link)
    endif()
  else()
    add_library(${_target} INTERFACE)
    target_include_directories(${_target} INTERFACE
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${_target} INTERFACE ${L_DEPENDS})
    target_compile_features(${_target} INTERFACE cxx_std_20)
  endif()
  set_target_properties(${_target} PROPERTIES EXPORT_NAME ${name})
  add_library(penalty::${name} ALIAS ${_target})
  set_property(GLOBAL APPEND PROPERTY PENALTY_INSTALL_TARGETS ${_target})
endfunction()
