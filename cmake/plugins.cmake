# One plugin per MeshLab build users run, from two shims over one core (one shim per plugin API;
# see filter_straightest_param/filter_definition.h):
#   build/plugins/meshlab-2020.09/        MeshFilterInterface shim: Debian 12's meshlab + meshlabserver
#   build/plugins/meshlab-2022.02/        FilterPlugin shim, float: Debian 13 (trixie) MeshLab
#   build/plugins/meshlab-2025.07-float/  FilterPlugin shim, float: Debian sid / Ubuntu 26.04 MeshLab,
#                                         the official 2025.07 AppImage
#   build/plugins/meshlab-2025.07/        FilterPlugin shim, double: pymeshlab 2025.7 (load_plugin),
#                                         the 2025.07d AppImage
# each holding libfilter_straightest_param.so. MeshLab 2022+ loads only a plugin of its own version
# (first 6 characters) and precision, hence a build each. Each compiles against its own MeshLab
# version's headers (src/common + vcglib), taken from the Debian source tarballs that
# scripts/fetch-meshlab-sources.sh extracts into the cache folder, and links that version's
# libmeshlab-common.so where one is on this machine (Debian 12's, pymeshlab's, or the one in the
# trixie/sid roots of scripts/make-meshlab-root.sh), so that every MeshLab symbol it uses is
# checked at link time. A missing source folder skips that plugin with a warning.

if(DEFINED ENV{SDP_CACHE_DIR})
  set(SDP_MESHLAB_CACHE_DIR "$ENV{SDP_CACHE_DIR}")
else()
  set(SDP_MESHLAB_CACHE_DIR "$ENV{HOME}/.cache/straightest-param")
endif()

# The source folder fetch-meshlab-sources.sh recorded for `version`, or "" when there is none.
function(sdp_recorded_meshlab_source version out_var)
  set(path_file "${SDP_MESHLAB_CACHE_DIR}/meshlab-${version}.path")
  set(dir "")
  if(EXISTS "${path_file}")
    file(STRINGS "${path_file}" dir LIMIT_COUNT 1)
  endif()
  set(${out_var} "${dir}" PARENT_SCOPE)
endfunction()

sdp_recorded_meshlab_source(2020.09 SDP_RECORDED_2020_SOURCE)
sdp_recorded_meshlab_source(2022.02 SDP_RECORDED_2022_SOURCE)
sdp_recorded_meshlab_source(2025.07 SDP_RECORDED_2025_SOURCE)
# A cache entry left empty by an earlier configure (before the fetch) is filled in now; a path
# the user set is kept.
function(sdp_cache_path var value type help)
  if(DEFINED CACHE{${var}} AND NOT "${${var}}" STREQUAL "")
    return()
  endif()
  set(${var} "${value}" CACHE ${type} "${help}" FORCE)
endfunction()

sdp_cache_path(MESHLAB_2020_SOURCE_DIR "${SDP_RECORDED_2020_SOURCE}" PATH
  "MeshLab 2020.09 source tree (src/common + vcglib); default: scripts/fetch-meshlab-sources.sh")
sdp_cache_path(MESHLAB_2022_SOURCE_DIR "${SDP_RECORDED_2022_SOURCE}" PATH
  "MeshLab 2022.02 source tree (src/common + src/vcglib); default: scripts/fetch-meshlab-sources.sh")
sdp_cache_path(MESHLAB_2025_SOURCE_DIR "${SDP_RECORDED_2025_SOURCE}" PATH
  "MeshLab 2025.07 source tree (src/common + src/vcglib); default: scripts/fetch-meshlab-sources.sh")

# Debian's MeshLab 2020.09 library the 2020.09 plugin links to, and where `cmake --install` puts it.
set(MESHLAB_2020_COMMON_LIBRARY "/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so" CACHE FILEPATH
    "libmeshlab-common.so of Debian's MeshLab 2020.09")
set(MESHLAB_2020_PLUGIN_INSTALL_DIR "/usr/lib/x86_64-linux-gnu/meshlab/plugins" CACHE PATH
    "Plugin folder of Debian's MeshLab 2020.09 (cmake --install; needs root)")
set(MESHLAB_2025_PLUGIN_INSTALL_DIR "lib/straightest_param/meshlab-2025.07" CACHE PATH
    "Where cmake --install puts the pymeshlab 2025.07 plugin (relative: under CMAKE_INSTALL_PREFIX)")

# pymeshlab's own libmeshlab-common.so (in the project's .venv): pymeshlab loads its library with
# RTLD_LOCAL, so a plugin that leaves MeshLab symbols undefined could not see them; linking the
# very file pymeshlab already loaded makes the loader reuse it by its soname.
set(SDP_PYTHON "${PROJECT_SOURCE_DIR}/.venv/bin/python" CACHE FILEPATH
    "Python with pymeshlab==2025.7.post1, pytest and numpy (scripts/install-deps.sh makes .venv)")
file(GLOB SDP_PYMESHLAB_COMMON_CANDIDATES
     "${PROJECT_SOURCE_DIR}/.venv/lib/python3*/site-packages/pymeshlab/lib/libmeshlab-common.so")
set(SDP_PYMESHLAB_COMMON_DEFAULT "")
if(SDP_PYMESHLAB_COMMON_CANDIDATES)
  list(SORT SDP_PYMESHLAB_COMMON_CANDIDATES)
  list(GET SDP_PYMESHLAB_COMMON_CANDIDATES -1 SDP_PYMESHLAB_COMMON_DEFAULT)
endif()
sdp_cache_path(MESHLAB_2025_COMMON_LIBRARY "${SDP_PYMESHLAB_COMMON_DEFAULT}" FILEPATH
  "pymeshlab's bundled libmeshlab-common.so (2025.07)")

set(SDP_BUILT_MESHLAB_PLUGINS "")

if(NOT EXISTS "${MESHLAB_2020_SOURCE_DIR}/src/common/interfaces.h"
   AND NOT EXISTS "${MESHLAB_2022_SOURCE_DIR}/src/common/plugins/interfaces/filter_plugin.h"
   AND NOT EXISTS "${MESHLAB_2025_SOURCE_DIR}/src/common/plugins/interfaces/filter_plugin.h")
  message(WARNING "No MeshLab sources found: skipping both MeshLab plugins. "
                  "Run scripts/fetch-meshlab-sources.sh or set MESHLAB_2020_SOURCE_DIR / MESHLAB_2025_SOURCE_DIR.")
  return()
endif()

find_package(Qt5 COMPONENTS Core Gui Widgets OpenGL Xml)
if(NOT Qt5_FOUND)
  message(WARNING "Qt5 (qtbase5-dev, libqt5opengl5-dev) not found: skipping the MeshLab plugins.")
  return()
endif()
find_package(OpenGL)
find_package(GLEW)

# Common settings of both shims: a Qt plugin module named libfilter_straightest_param.so in its
# own version folder, the core linked statically, MeshLab/vcglib headers as system headers (their
# warnings are not ours). Default visibility on purpose: MLException thrown here must match the
# one pymeshlab catches.
function(sdp_add_meshlab_plugin target version scalar)
  cmake_parse_arguments(ARG "ALLOW_UNDEFINED" "FOLDER" "SOURCES;INCLUDE_DIRS;LIBRARIES" ${ARGN})
  if(NOT ARG_FOLDER)
    set(ARG_FOLDER "meshlab-${version}")
  endif()
  add_library(${target} MODULE ${ARG_SOURCES})
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME filter_straightest_param
    LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/plugins/${ARG_FOLDER}"
    AUTOMOC ON)
  target_include_directories(${target} SYSTEM PRIVATE ${ARG_INCLUDE_DIRS})
  target_include_directories(${target} PRIVATE "${PROJECT_SOURCE_DIR}")
  target_compile_definitions(${target} PRIVATE MESHLAB_SCALAR=${scalar} MESHLAB_VERSION=${version})
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  target_link_libraries(${target} PRIVATE sdp_filter_definition Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml
                        ${ARG_LIBRARIES})
  # Our static core must not leak symbols that could clash with MeshLab's.
  target_link_options(${target} PRIVATE -Wl,--exclude-libs,ALL)
  if(NOT ARG_ALLOW_UNDEFINED)
    # A symbol missing at load time kills the host process (pymeshlab exits with "symbol lookup
    # error"): every symbol must resolve when linking.
    target_link_options(${target} PRIVATE -Wl,-z,defs)
  endif()
endfunction()

# --- MeshLab 2020.09 (Debian meshlab, meshlabserver) ------------------------------------------
if(NOT EXISTS "${MESHLAB_2020_SOURCE_DIR}/src/common/interfaces.h")
  message(WARNING "MeshLab 2020.09 sources not found (MESHLAB_2020_SOURCE_DIR='${MESHLAB_2020_SOURCE_DIR}'): "
                  "skipping the 2020.09 plugin. Run scripts/fetch-meshlab-sources.sh.")
elseif(NOT EXISTS "${MESHLAB_2020_COMMON_LIBRARY}")
  message(WARNING "${MESHLAB_2020_COMMON_LIBRARY} not found (Debian package meshlab): "
                  "skipping the 2020.09 plugin.")
elseif(NOT GLEW_FOUND OR NOT OPENGL_FOUND)
  message(WARNING "GLEW/OpenGL (libglew-dev) not found: skipping the 2020.09 plugin.")
else()
  sdp_add_meshlab_plugin(filter_straightest_param_meshlab2020 2020.09 float
    SOURCES
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2020/filter_straightest_param.h
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2020/filter_straightest_param.cpp
    INCLUDE_DIRS
      "${MESHLAB_2020_SOURCE_DIR}/src" "${MESHLAB_2020_SOURCE_DIR}/src/common"
      "${MESHLAB_2020_SOURCE_DIR}/vcglib"
    LIBRARIES GLEW::GLEW OpenGL::GL "${MESHLAB_2020_COMMON_LIBRARY}")
  install(TARGETS filter_straightest_param_meshlab2020
          LIBRARY DESTINATION "${MESHLAB_2020_PLUGIN_INSTALL_DIR}" COMPONENT meshlab2020)
  list(APPEND SDP_BUILT_MESHLAB_PLUGINS meshlab-2020.09)
endif()

# --- MeshLab 2025.07 (pymeshlab 2025.7) ------------------------------------------------------
if(NOT EXISTS "${MESHLAB_2025_SOURCE_DIR}/src/common/plugins/interfaces/filter_plugin.h")
  message(WARNING "MeshLab 2025.07 sources not found (MESHLAB_2025_SOURCE_DIR='${MESHLAB_2025_SOURCE_DIR}'): "
                  "skipping the 2025.07 plugin. Run scripts/fetch-meshlab-sources.sh.")
else()
  set(SDP_2025_LIBRARIES "")
  set(SDP_2025_ALLOW_UNDEFINED "")
  if(EXISTS "${MESHLAB_2025_COMMON_LIBRARY}")
    get_filename_component(SDP_PYMESHLAB_LIB_DIR "${MESHLAB_2025_COMMON_LIBRARY}" DIRECTORY)
    # rpath-link: let ld find that library's own dependencies (its Qt, GLEW) at link time only.
    set(SDP_2025_LIBRARIES "${MESHLAB_2025_COMMON_LIBRARY}" "-Wl,-rpath-link,${SDP_PYMESHLAB_LIB_DIR}")
  else()
    message(WARNING "pymeshlab's libmeshlab-common.so not found (MESHLAB_2025_COMMON_LIBRARY): the 2025.07 "
                    "plugin leaves MeshLab symbols undefined. Run scripts/install-deps.sh, then re-configure.")
    set(SDP_2025_ALLOW_UNDEFINED ALLOW_UNDEFINED)
  endif()
  # The scalar must match the running MeshLab: pymeshlab refuses a plugin of the other precision
  # ("different floating point precision"). The pymeshlab 2025.7.post1 wheel is built with
  # MESHLAB_SCALAR=double (its RichPosition takes Point3<double>); read it from the library.
  if(NOT DEFINED MESHLAB_2025_SCALAR AND EXISTS "${MESHLAB_2025_COMMON_LIBRARY}")
    set(SDP_DETECTED_2025_SCALAR double)
    execute_process(COMMAND nm -DC "${MESHLAB_2025_COMMON_LIBRARY}" OUTPUT_VARIABLE SDP_NM_OUTPUT
                    ERROR_QUIET RESULT_VARIABLE SDP_NM_RESULT)
    if(SDP_NM_RESULT EQUAL 0 AND SDP_NM_OUTPUT MATCHES "RichPosition::RichPosition\\([^)]*Point3<float>")
      set(SDP_DETECTED_2025_SCALAR float)
    endif()
  else()
    set(SDP_DETECTED_2025_SCALAR double)
  endif()
  set(MESHLAB_2025_SCALAR "${SDP_DETECTED_2025_SCALAR}" CACHE STRING
      "MESHLAB_SCALAR of the MeshLab 2025.07 the plugin runs in (pymeshlab 2025.7.post1: double)")
  set_property(CACHE MESHLAB_2025_SCALAR PROPERTY STRINGS float double)
  sdp_add_meshlab_plugin(filter_straightest_param_meshlab2025 2025.07 ${MESHLAB_2025_SCALAR}
    ${SDP_2025_ALLOW_UNDEFINED}
    SOURCES
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2025/filter_straightest_param.h
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2025/filter_straightest_param.cpp
    INCLUDE_DIRS
      "${MESHLAB_2025_SOURCE_DIR}/src" "${MESHLAB_2025_SOURCE_DIR}/src/common"
      "${MESHLAB_2025_SOURCE_DIR}/src/vcglib"
    LIBRARIES ${SDP_2025_LIBRARIES})
  # No RUNPATH into .venv: pymeshlab has loaded every library the plugin needs before loading it.
  set_target_properties(filter_straightest_param_meshlab2025 PROPERTIES SKIP_BUILD_RPATH ON)
  install(TARGETS filter_straightest_param_meshlab2025
          LIBRARY DESTINATION "${MESHLAB_2025_PLUGIN_INSTALL_DIR}" COMPONENT meshlab2025)
  # Opt-in: copy the plugin into pymeshlab's own plugin folder, so that `import pymeshlab` loads
  # it and binds MeshSet.compute_texcoord_parametrization_straightest_distances like a built-in
  # (pymeshlab binds methods only for plugins present at import; after load_plugin() use
  # ms.apply_filter(name, ...) or tests/python/conftest.py's binding).
  #   cmake --build build --target pymeshlab_install_plugin
  if(EXISTS "${MESHLAB_2025_COMMON_LIBRARY}")
    add_custom_target(pymeshlab_install_plugin
      COMMAND ${CMAKE_COMMAND} -E copy "$<TARGET_FILE:filter_straightest_param_meshlab2025>"
              "${SDP_PYMESHLAB_LIB_DIR}/plugins/"
      DEPENDS filter_straightest_param_meshlab2025
      COMMENT "Copying the 2025.07 plugin into ${SDP_PYMESHLAB_LIB_DIR}/plugins")
  endif()
  list(APPEND SDP_BUILT_MESHLAB_PLUGINS meshlab-2025.07)
endif()

# --- MeshLab 2022.02 and 2025.07 float GUIs (Debian trixie, Debian sid / Ubuntu 26.04) ---------
# The FilterPlugin shim again, float, against each version's own headers. Their libmeshlab-common.so
# comes from the Debian roots the tests run these GUIs in (scripts/make-meshlab-root.sh): linking it
# checks every MeshLab symbol the plugin uses against that very build. Its own dependencies need a
# newer glibc than this machine's, so they are not resolved here (--allow-shlib-undefined); the
# plugin itself only needs this machine's glibc, which every newer release carries.
set(SDP_MESHLAB_ROOTS_DIR "${SDP_MESHLAB_CACHE_DIR}/roots" CACHE PATH
    "Debian roots with MeshLab 2022.02 (trixie/) and 2025.07 (sid/) (scripts/make-meshlab-root.sh)")
function(sdp_add_filter_plugin_gui_build target version folder suite source_dir component)
  set(common "${SDP_MESHLAB_ROOTS_DIR}/${suite}/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so")
  string(REPLACE "." "_" version_id "${version}")
  set(MESHLAB_${version_id}_${suite}_COMMON_LIBRARY "${common}" CACHE FILEPATH
      "libmeshlab-common.so of the MeshLab ${version} the ${folder} plugin runs in")
  set(common "${MESHLAB_${version_id}_${suite}_COMMON_LIBRARY}")
  if(NOT EXISTS "${source_dir}/src/common/plugins/interfaces/filter_plugin.h")
    message(WARNING "MeshLab ${version} sources not found ('${source_dir}'): skipping the ${folder} "
                    "plugin. Run scripts/fetch-meshlab-sources.sh.")
    return()
  endif()
  set(libraries "")
  set(allow_undefined ALLOW_UNDEFINED)
  if(EXISTS "${common}")
    set(libraries "${common}" "-Wl,--allow-shlib-undefined")
    set(allow_undefined "")
  else()
    message(WARNING "${common} not found (scripts/make-meshlab-root.sh ${suite}): the ${folder} "
                    "plugin leaves MeshLab symbols unchecked until MeshLab loads it.")
  endif()
  sdp_add_meshlab_plugin(${target} ${version} float ${allow_undefined} FOLDER ${folder}
    SOURCES
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2025/filter_straightest_param.h
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/meshlab2025/filter_straightest_param.cpp
    INCLUDE_DIRS
      "${source_dir}/src" "${source_dir}/src/common" "${source_dir}/src/vcglib"
    LIBRARIES ${libraries})
  # MeshLab has loaded its libmeshlab-common.so (by this soname) before any plugin.
  set_target_properties(${target} PROPERTIES SKIP_BUILD_RPATH ON)
  # Not into this machine's MeshLab (2020.09): the README says where each goes on its system.
  install(TARGETS ${target} LIBRARY DESTINATION "lib/straightest_param/${folder}"
          COMPONENT ${component})
  # What tests/meshlab_roots needs to run this build in its root, said once, here.
  set_target_properties(${target} PROPERTIES SDP_MESHLAB_VERSION ${version}
                        SDP_MESHLAB_SOURCE_DIR "${source_dir}" SDP_ROOT_SUITE ${suite}
                        SDP_MESHLAB_COMMON_LIBRARY "${common}")
  set_property(GLOBAL APPEND PROPERTY SDP_ROOT_PLUGIN_TARGETS ${target})
  set(SDP_BUILT_MESHLAB_PLUGINS ${SDP_BUILT_MESHLAB_PLUGINS} ${folder} PARENT_SCOPE)
endfunction()
sdp_add_filter_plugin_gui_build(filter_straightest_param_meshlab2022 2022.02 meshlab-2022.02 trixie
                                "${MESHLAB_2022_SOURCE_DIR}" meshlab2022)
sdp_add_filter_plugin_gui_build(filter_straightest_param_meshlab2025_float 2025.07
                                meshlab-2025.07-float sid "${MESHLAB_2025_SOURCE_DIR}" meshlab2025float)

if(SDP_BUILT_MESHLAB_PLUGINS)
  install(FILES "${PROJECT_SOURCE_DIR}/resources/straightest_param.mlx"
          DESTINATION share/straightest_param COMPONENT meshlab2020)
endif()
message(STATUS "MeshLab plugins: ${SDP_BUILT_MESHLAB_PLUGINS}")
