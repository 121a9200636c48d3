# The viewer page (viewer/index.html, viewer/viewer.js and the vendored three.js) embedded into
# penalty::output as a generated source, regenerated when one of the files changes.
function(penalty_embed_viewer_assets target)
  set(_dir ${PROJECT_SOURCE_DIR}/viewer)
  set(_files
    index.html=${_dir}/index.html
    viewer.js=${_dir}/viewer.js
    three.module.min.js=${_dir}/vendor/three.module.min.js
    OrbitControls.js=${_dir}/vendor/OrbitControls.js
    THREE_LICENSE=${_dir}/vendor/THREE_LICENSE)
  set(_paths "")
  foreach(_entry IN LISTS _files)
    string(REGEX REPLACE "^[^=]*=" "" _path "${_entry}")
    list(APPEND _paths ${_path})
  endforeach()
  set(_out ${PROJECT_BINARY_DIR}/generated/viewer_assets.cpp)
  string(REPLACE ";" "|" _files_arg "${_files}")
  add_custom_command(
    OUTPUT ${_out}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${_out} "-DFILES=${_files_arg}" -P ${PROJECT_SOURCE_DIR}/cmake/PenaltyEmbedFiles.cmake
    DEPENDS ${_paths} ${PROJECT_SOURCE_DIR}/cmake/PenaltyEmbedFiles.cmake
    COMMENT "Embedding the viewer page (viewer/) into penalty::output"
    VERBATIM)
  target_sources(${target} PRIVATE ${_out})
endfunction()
