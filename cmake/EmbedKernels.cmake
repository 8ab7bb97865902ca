# Embeds OpenCL C sources into a generated C++ file as byte arrays, regenerated whenever a .cl file changes.
# At run time host/cl/kernel_source.cpp looks them up by file name (e.g. "util.cl").
set(CLR_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_kernels_script.cmake)

function(clr_embed_kernels output)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} "-DINPUTS=${ARGN}" -P ${CLR_EMBED_SCRIPT}
    DEPENDS ${ARGN} ${CLR_EMBED_SCRIPT}
    COMMENT "Embedding OpenCL kernels"
    VERBATIM)
endfunction()

# The same for other files embedded by name (the report page's HTML, JS and CSS, report/): NAMESPACE::FUNCTION()
# returns their map.
function(clr_embed_files output namespace function)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} "-DINPUTS=${ARGN}" -DNAMESPACE=${namespace} -DFUNCTION=${function}
            -P ${CLR_EMBED_SCRIPT}
    DEPENDS ${ARGN} ${CLR_EMBED_SCRIPT}
    COMMENT "Embedding ${function}"
    VERBATIM)
endfunction()
