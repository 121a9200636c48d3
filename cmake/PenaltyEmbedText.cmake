# penalty_embed_text(TARGET FILE FUNCTION): FILE embedded into TARGET as a generated source that
# defines `std::string_view FUNCTION()` (a qualified name, e.g. penalty::scene::sofa_data_catalog_text),
# regenerated when FILE changes. The bytes are written as an array (no string-literal length limit).
function(penalty_embed_text target file function)
  get_filename_component(_stem ${file} NAME_WE)
  set(_out ${PROJECT_BINARY_DIR}/generated/${_stem}_text.cpp)
  add_custom_command(
    OUTPUT ${_out}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${_out} -DINPUT=${file} -DFUNCTION=${function}
            -P ${PROJECT_SOURCE_DIR}/cmake/PenaltyEmbedTextScript.cmake
    DEPENDS ${file} ${PROJECT_SOURCE_DIR}/cmake/PenaltyEmbedTextScript.cmake
    COMMENT "Embedding ${_stem} into ${target}"
    VERBATIM)
  target_sources(${target} PRIVATE ${_out})
endfunction()
