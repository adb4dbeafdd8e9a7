# Compiles hydrolux's shaders with glslangValidator (Debian package glslang-tools); any error fails.
#   cmake -DSHADER_DIR=<repo>/data/shaders -DWORK_DIR=<scratch dir> [-DGLSLANG=<path>] -P check_shaders.cmake
# GLSL: the version-less function files are concatenated behind "#version 300 es" (WebGL2) and
# behind "#version 450", each with default precisions, then compiled as the stage of each main
# (example.frag, cubemap_bake.frag, halfdome.frag, halfdome.vert). HLSL: each entry point with
# -V -D -e <entry> -S <stage> (HLSL needs SPIR-V code generation). A deliberately broken shader must fail too (the validator is live).
cmake_minimum_required(VERSION 3.20)
foreach(v SHADER_DIR WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check_shaders.cmake: pass -D${v}=...")
  endif()
endforeach()
if(NOT GLSLANG)
  find_program(GLSLANG NAMES glslangValidator glslang)
endif()
if(NOT GLSLANG OR NOT EXISTS "${GLSLANG}")
  message(FATAL_ERROR "glslangValidator not found: install the Debian package glslang-tools "
                      "(apt-get install glslang-tools, or scripts/install-deps)")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(failures 0)
function(run_validator label)
  execute_process(COMMAND "${GLSLANG}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(SEND_ERROR "FAIL ${label}:\n${out}${err}")
    math(EXPR n "${failures} + 1")
    set(failures ${n} PARENT_SCOPE)
  else()
    message(STATUS "ok   ${label}")
  endif()
endfunction()

set(glsl "${SHADER_DIR}/glsl")
set(functions hydrolux_common.glsl hydrolux_sky.glsl hydrolux_rainbow.glsl hydrolux_composite.glsl)
foreach(f IN LISTS functions ITEMS example.frag cubemap_bake.frag halfdome.frag halfdome.vert)
  if(NOT EXISTS "${glsl}/${f}")
    message(FATAL_ERROR "missing shader ${glsl}/${f}")
  endif()
endforeach()

# main file -> the function files it needs (all of them: unused functions cost nothing).
set(precisions "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\nprecision highp samplerCube;\n")
foreach(version "300 es" "450")
  string(REPLACE " " "" vtag "${version}")
  foreach(main example.frag cubemap_bake.frag halfdome.frag halfdome.vert)
    set(text "#version ${version}\n${precisions}")
    if(NOT main MATCHES "\\.vert$")
      foreach(f IN LISTS functions)
        file(READ "${glsl}/${f}" body)
        string(APPEND text "${body}\n")
      endforeach()
    endif()
    file(READ "${glsl}/${main}" body)
    string(APPEND text "${body}")
    get_filename_component(stem "${main}" NAME_WE)
    get_filename_component(ext "${main}" LAST_EXT)
    set(out "${WORK_DIR}/${stem}_${vtag}${ext}")
    file(WRITE "${out}" "${text}")
    run_validator("GLSL ${version} ${main}" "${out}")
  endforeach()
endforeach()

set(hlsl "${SHADER_DIR}/hlsl")
foreach(entry
    "example.hlsl|hx_example_ps|frag" "example.hlsl|hx_fullscreen_vs|vert"
    "cubemap_bake.hlsl|hx_cube_bake_ps|frag" "halfdome.hlsl|hx_halfdome_vs|vert"
    "halfdome.hlsl|hx_halfdome_ps|frag")
  string(REPLACE "|" ";" parts "${entry}")
  list(GET parts 0 file)
  list(GET parts 1 ep)
  list(GET parts 2 stage)
  if(NOT EXISTS "${hlsl}/${file}")
    message(FATAL_ERROR "missing shader ${hlsl}/${file}")
  endif()
  run_validator("HLSL ${file} ${ep}" -V -D -e ${ep} -S ${stage} -o "${WORK_DIR}/${ep}.spv" "${hlsl}/${file}")
endforeach()

# The validator must reject a broken shader (else this test proves nothing).
file(WRITE "${WORK_DIR}/broken.frag" "#version 300 es\nprecision highp float;\nout vec4 c;\nvoid main() { c = vec3(1.0); }\n")
execute_process(COMMAND "${GLSLANG}" "${WORK_DIR}/broken.frag" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(rc EQUAL 0)
  message(SEND_ERROR "FAIL glslangValidator accepted a broken shader")
  math(EXPR failures "${failures} + 1")
endif()

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} shader compilation(s) failed")
endif()
message(STATUS "all shaders compile")
