# One plugin per MeshLab build users run, one per row of meshlab-builds.tsv (folder, version,
# plugin API, precision, where it runs), from one shim per plugin API over one core (see
# filter_straightest_param/filter_definition.h):
#   build/plugins/<folder>/libfilter_straightest_param.so        target plugin_<folder>
# MeshLab 2022+ loads only a plugin of its own version (first 6 characters) and precision, hence a
# build each. Each compiles against its own MeshLab version's headers (src/common + vcglib), taken
# from the Debian source tarballs that scripts/fetch-meshlab-sources.sh extracts into the cache
# folder, and links that version's libmeshlab-common.so where one is on this machine (Debian 12's
# for the host row, pymeshlab's, or the one in the row's Debian root of
# scripts/make-meshlab-root.sh), so that every MeshLab symbol it uses is checked at link time. A
# missing source folder skips that plugin with a warning.
# The tests find the builds as SDP_HOST_PLUGIN_TARGET (this machine's MeshLab and meshlabserver),
# SDP_PYMESHLAB_PLUGIN_TARGET (pymeshlab 2025.7.post1, the .venv), and the global properties
# SDP_ROOT_PLUGIN_TARGETS and SDP_OLDER_PYMESHLAB_TARGETS (older pymeshlab wheels pipelines pin).
# A row's `source` names the source tree it compiles against, its `version` the MeshLab version
# it declares (MESHLAB_VERSION): pymeshlab 2023.12 has no Debian source, and its plugin API is
# 2025.07's.

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

# A cache entry left empty by an earlier configure (before the fetch) is filled in now; a path
# the user set is kept.
function(sdp_cache_path var value type help)
  if(DEFINED CACHE{${var}} AND NOT "${${var}}" STREQUAL "")
    return()
  endif()
  set(${var} "${value}" CACHE ${type} "${help}" FORCE)
endfunction()

file(STRINGS "${PROJECT_SOURCE_DIR}/meshlab-builds.tsv" SDP_MESHLAB_BUILD_ROWS REGEX "^[^#]")

# Each source version's tree (column `source`), once per version; the last one found (the table
# runs oldest first) is SDP_NEWEST_MESHLAB_SOURCE_DIR, whose vcglib the bench's reader comparison
# uses. SDP_MESHLAB_SOURCE_VERSIONS lists them (the vcglib adapter tests build once per source).
set(SDP_ANY_MESHLAB_SOURCE FALSE)
set(SDP_NEWEST_MESHLAB_SOURCE_DIR "")
set(SDP_MESHLAB_SOURCE_VERSIONS "")
foreach(row IN LISTS SDP_MESHLAB_BUILD_ROWS)
  string(REPLACE "\t" ";" fields "${row}")
  list(GET fields 10 version)
  if(version IN_LIST SDP_MESHLAB_SOURCE_VERSIONS)
    continue()
  endif()
  list(APPEND SDP_MESHLAB_SOURCE_VERSIONS ${version})
  string(REPLACE "." "_" version_id "${version}")
  sdp_recorded_meshlab_source(${version} recorded)
  sdp_cache_path(MESHLAB_SOURCE_DIR_${version_id} "${recorded}" PATH
    "MeshLab ${version} source tree (src/common + vcglib); default: scripts/fetch-meshlab-sources.sh")
  if(EXISTS "${MESHLAB_SOURCE_DIR_${version_id}}/src/common")
    set(SDP_ANY_MESHLAB_SOURCE TRUE)
    set(SDP_NEWEST_MESHLAB_SOURCE_DIR "${MESHLAB_SOURCE_DIR_${version_id}}")
  endif()
endforeach()

# Debian's MeshLab library the host row's plugin links to, and where `cmake --install` puts it.
set(MESHLAB_HOST_COMMON_LIBRARY "/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so" CACHE FILEPATH
    "libmeshlab-common.so of this machine's Debian MeshLab")
set(MESHLAB_HOST_PLUGIN_INSTALL_DIR "/usr/lib/x86_64-linux-gnu/meshlab/plugins" CACHE PATH
    "Plugin folder of this machine's Debian MeshLab (cmake --install; needs root)")

# pymeshlab's own libmeshlab-common.so, in the project's .venv (sdp_add_meshlab_build says why).
set(SDP_PYTHON "${PROJECT_SOURCE_DIR}/.venv/bin/python" CACHE FILEPATH
    "Python with pymeshlab==2025.7.post1, pytest and numpy (scripts/install-deps.sh makes .venv)")

# The virtual environment of a pymeshlab row (runs_in `pymeshlab`: .venv; `pymeshlab-VERSION`:
# .venv-pymeshlab-VERSION, scripts/install-deps.sh makes both) and its libmeshlab-common.so ("" when
# it is not there yet).
function(sdp_pymeshlab_venv runs_in venv_var common_var)
  if(runs_in STREQUAL "pymeshlab")
    set(venv "${PROJECT_SOURCE_DIR}/.venv")
  else()
    set(venv "${PROJECT_SOURCE_DIR}/.venv-${runs_in}")
  endif()
  file(GLOB candidates "${venv}/lib/python3*/site-packages/pymeshlab/lib/libmeshlab-common.so")
  set(common "")
  if(candidates)
    list(SORT candidates)
    list(GET candidates -1 common)
  endif()
  set(${venv_var} "${venv}" PARENT_SCOPE)
  set(${common_var} "${common}" PARENT_SCOPE)
endfunction()
sdp_pymeshlab_venv(pymeshlab SDP_MAIN_VENV SDP_PYMESHLAB_COMMON_DEFAULT)
sdp_cache_path(MESHLAB_PYMESHLAB_COMMON_LIBRARY "${SDP_PYMESHLAB_COMMON_DEFAULT}" FILEPATH
  "pymeshlab's bundled libmeshlab-common.so (the .venv's, pymeshlab 2025.7.post1)")

set(SDP_BUILT_MESHLAB_PLUGINS "")
if(NOT SDP_ANY_MESHLAB_SOURCE)
  message(WARNING "No MeshLab sources found: skipping the MeshLab plugins. "
                  "Run scripts/fetch-meshlab-sources.sh or set MESHLAB_SOURCE_DIR_<version>.")
  return()
endif()

find_package(Qt5 COMPONENTS Core Gui Widgets OpenGL Xml)
if(NOT Qt5_FOUND)
  message(WARNING "Qt5 (qtbase5-dev, libqt5opengl5-dev) not found: skipping the MeshLab plugins.")
  return()
endif()
find_package(OpenGL)
find_package(GLEW)

# Common settings of every build: a Qt plugin module named libfilter_straightest_param.so in its
# own build folder, the core linked statically, MeshLab/vcglib headers as system headers (their
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

# What a plugin API's shim needs: the header that shows a source tree has that API, where its
# vcglib is, and what its headers pull in (MeshFilterInterface's include GLEW).
function(sdp_meshlab_api api)
  if(api STREQUAL "mesh_filter_interface")
    set(api_header "src/common/interfaces.h" PARENT_SCOPE)
    set(api_vcglib "vcglib" PARENT_SCOPE)
    if(GLEW_FOUND AND OPENGL_FOUND)
      set(api_libraries GLEW::GLEW OpenGL::GL PARENT_SCOPE)
      set(api_missing "" PARENT_SCOPE)
    else()
      set(api_missing "GLEW/OpenGL (libglew-dev)" PARENT_SCOPE)
    endif()
  elseif(api STREQUAL "filter_plugin")
    set(api_header "src/common/plugins/interfaces/filter_plugin.h" PARENT_SCOPE)
    set(api_vcglib "src/vcglib" PARENT_SCOPE)
    set(api_libraries "" PARENT_SCOPE)
    set(api_missing "" PARENT_SCOPE)
  else()
    message(FATAL_ERROR "meshlab-builds.tsv: unknown plugin API '${api}' (a shim folder of filter_straightest_param/)")
  endif()
endfunction()

set(SDP_MESHLAB_ROOTS_DIR "${SDP_MESHLAB_CACHE_DIR}/roots" CACHE PATH
    "Debian roots holding the newer MeshLab GUIs, one folder per suite (scripts/make-meshlab-root.sh)")

# The common library a build links (where one is on this machine) and how: the host's Debian
# MeshLab, pymeshlab's own library, or the one in the row's Debian root.
#   pymeshlab: pymeshlab loads its library with RTLD_LOCAL, so a plugin that left MeshLab symbols
#     undefined could not see them; linking the very file pymeshlab already loaded makes the
#     loader reuse it by its soname.
#   a root: its library needs a newer glibc than this machine's, so its own dependencies are not
#     resolved here (--allow-shlib-undefined); the plugin itself only needs this machine's glibc,
#     which every newer release carries.
function(sdp_add_meshlab_build row)
  string(REPLACE "\t" ";" fields "${row}")
  list(GET fields 0 folder)
  list(GET fields 1 version)
  list(GET fields 2 api)
  list(GET fields 3 scalar)
  list(GET fields 4 runs_in)
  list(GET fields 10 source_version)
  string(REPLACE "." "_" source_id "${source_version}")
  set(source_dir "${MESHLAB_SOURCE_DIR_${source_id}}")
  set(target plugin_${folder})
  sdp_meshlab_api(${api})
  if(NOT EXISTS "${source_dir}/${api_header}")
    message(WARNING "MeshLab ${source_version} sources not found (MESHLAB_SOURCE_DIR_${source_id}="
                    "'${source_dir}'): skipping the ${folder} plugin. Run scripts/fetch-meshlab-sources.sh.")
    return()
  endif()
  if(api_missing)
    message(WARNING "${api_missing} not found: skipping the ${folder} plugin.")
    return()
  endif()

  set(libraries ${api_libraries})
  set(allow_undefined "")
  # Not into this machine's MeshLab unless it is the host's: docs/meshlab.md says where each goes.
  set(install_dir "lib/straightest_param/${folder}")
  if(runs_in STREQUAL "host")
    if(NOT EXISTS "${MESHLAB_HOST_COMMON_LIBRARY}")
      message(WARNING "${MESHLAB_HOST_COMMON_LIBRARY} not found (Debian package meshlab): "
                      "skipping the ${folder} plugin.")
      return()
    endif()
    list(APPEND libraries "${MESHLAB_HOST_COMMON_LIBRARY}")
    set(install_dir "${MESHLAB_HOST_PLUGIN_INSTALL_DIR}")
  elseif(runs_in MATCHES "^pymeshlab")
    if(runs_in STREQUAL "pymeshlab")
      set(venv "${SDP_MAIN_VENV}")
      set(common "${MESHLAB_PYMESHLAB_COMMON_LIBRARY}")
    else()
      sdp_pymeshlab_venv(${runs_in} venv common)
    endif()
    if(EXISTS "${common}")
      get_filename_component(lib_dir "${common}" DIRECTORY)
      # rpath-link: let ld find that library's own dependencies (its Qt, GLEW) at link time only.
      list(APPEND libraries "${common}" "-Wl,-rpath-link,${lib_dir}")
      # The scalar must match the running MeshLab: pymeshlab refuses a plugin of the other
      # precision ("different floating point precision"). Read it from the library (its
      # RichPosition takes a Point3 of that scalar); the table's value when it cannot be read.
      execute_process(COMMAND nm -DC "${common}" OUTPUT_VARIABLE nm_output ERROR_QUIET
                      RESULT_VARIABLE nm_result)
      if(nm_result EQUAL 0 AND nm_output MATCHES "RichPosition::RichPosition\\([^)]*Point3<float>")
        set(scalar float)
      elseif(nm_result EQUAL 0 AND nm_output MATCHES "RichPosition::RichPosition\\([^)]*Point3<double>")
        set(scalar double)
      endif()
    else()
      message(WARNING "pymeshlab's libmeshlab-common.so not found in ${venv}: "
                      "the ${folder} plugin leaves MeshLab symbols undefined. Run "
                      "scripts/install-deps.sh, then re-configure.")
      set(allow_undefined ALLOW_UNDEFINED)
    endif()
  else()
    set(common "${SDP_MESHLAB_ROOTS_DIR}/${runs_in}/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so")
    if(EXISTS "${common}")
      list(APPEND libraries "${common}" "-Wl,--allow-shlib-undefined")
    else()
      message(WARNING "${common} not found (scripts/make-meshlab-root.sh ${runs_in}): the ${folder} "
                      "plugin leaves MeshLab symbols unchecked until MeshLab loads it.")
      set(allow_undefined ALLOW_UNDEFINED)
    endif()
  endif()

  sdp_add_meshlab_plugin(${target} ${version} ${scalar} ${allow_undefined} FOLDER ${folder}
    SOURCES
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/${api}/filter_straightest_param.h
      ${PROJECT_SOURCE_DIR}/filter_straightest_param/${api}/filter_straightest_param.cpp
    INCLUDE_DIRS
      "${source_dir}/src" "${source_dir}/src/common" "${source_dir}/${api_vcglib}"
    LIBRARIES ${libraries})
  if(NOT runs_in STREQUAL "host")
    # The host process (MeshLab, pymeshlab) has loaded its libmeshlab-common.so, by this soname,
    # before any plugin: no RUNPATH.
    set_target_properties(${target} PROPERTIES SKIP_BUILD_RPATH ON)
  endif()
  install(TARGETS ${target} LIBRARY DESTINATION "${install_dir}" COMPONENT ${folder})

  if(runs_in STREQUAL "host")
    set(SDP_HOST_PLUGIN_TARGET ${target} PARENT_SCOPE)
    set(SDP_HOST_PLUGIN_FOLDER ${folder} PARENT_SCOPE)
  elseif(runs_in MATCHES "^pymeshlab-")
    # An older pymeshlab a pipeline may pin: its tests run in its own .venv-pymeshlab-VERSION.
    set_target_properties(${target} PROPERTIES SDP_VENV "${venv}" SDP_RUNS_IN ${runs_in})
    set_property(GLOBAL APPEND PROPERTY SDP_OLDER_PYMESHLAB_TARGETS ${target})
  elseif(runs_in STREQUAL "pymeshlab")
    set(SDP_PYMESHLAB_PLUGIN_TARGET ${target} PARENT_SCOPE)
    # Opt-in: copy the plugin into pymeshlab's own plugin folder, so that `import pymeshlab`
    # loads it and binds MeshSet.compute_texcoord_parametrization_straightest_distances like a
    # built-in (pymeshlab binds methods only for plugins present at import; after load_plugin()
    # use ms.apply_filter(name, ...) or tests/python/conftest.py's binding).
    #   cmake --build build --target pymeshlab_install_plugin
    if(EXISTS "${common}")
      add_custom_target(pymeshlab_install_plugin
        COMMAND ${CMAKE_COMMAND} -E copy "$<TARGET_FILE:${target}>" "${lib_dir}/plugins/"
        DEPENDS ${target}
        COMMENT "Copying the ${folder} plugin into ${lib_dir}/plugins")
    endif()
  else()
    # What tests/meshlab_roots needs to run this build in its root, said once, here.
    set_target_properties(${target} PROPERTIES SDP_MESHLAB_VERSION ${version}
                          SDP_MESHLAB_SOURCE_DIR "${source_dir}" SDP_ROOT_SUITE ${runs_in}
                          SDP_MESHLAB_COMMON_LIBRARY "${common}")
    set_property(GLOBAL APPEND PROPERTY SDP_ROOT_PLUGIN_TARGETS ${target})
  endif()
  set(SDP_BUILT_MESHLAB_PLUGINS ${SDP_BUILT_MESHLAB_PLUGINS} ${folder} PARENT_SCOPE)
endfunction()

foreach(row IN LISTS SDP_MESHLAB_BUILD_ROWS)
  sdp_add_meshlab_build("${row}")
endforeach()

# The example script goes with the host's meshlabserver plugin.
if(SDP_HOST_PLUGIN_FOLDER)
  install(FILES "${PROJECT_SOURCE_DIR}/resources/straightest_param.mlx"
          DESTINATION share/straightest_param COMPONENT ${SDP_HOST_PLUGIN_FOLDER})
endif()
message(STATUS "MeshLab plugins: ${SDP_BUILT_MESHLAB_PLUGINS}")
