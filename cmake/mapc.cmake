# mapc.cmake: generate RMF map outputs with mapc at build time.
#
#   include(mapc)   # with this directory on CMAKE_MODULE_PATH, or include(<path>/mapc.cmake)
#   mapc_generate_maps(
#     TARGET <name>                      # custom target building every map (part of ALL)
#     MAPS <file.building.yaml>...       # maps, relative to the current source directory
#     [OUTPUT_DIR <dir>]                 # default ${CMAKE_CURRENT_BINARY_DIR}/maps
#     [INSTALL_DESTINATION <dir>]        # default share/${PROJECT_NAME}/maps
#     [TARGETS <nav|gltf|meshes|classic|ignition|gz>...]  # default: all of them
#     [TEXTURE_PATHS <dir>...]           # searched for <texture>.png before the map's dir
#     [NO_INSTALL])
#
# For each map, one custom command runs
#   mapc build <map> -o <OUTPUT_DIR> --stamp <stamp> --depfile <depfile>
# writing <OUTPUT_DIR>/<map>/ (nav_graphs/<i>.yaml, <building>.glb, models/...), where
# <map> is the file name less `.building.yaml`. The command reruns only when the map, a
# texture it read, or the mapc executable changed: through DEPFILE where the generator
# supports it (Ninja; Makefiles from CMake 3.20; Xcode and Visual Studio from 3.21),
# otherwise through DEPENDS on the map. mapc does not rewrite files whose content did not
# change; files a previous run wrote and this one did not are removed (mapc keeps a
# manifest, .mapc-manifest, which is not installed). Each <OUTPUT_DIR>/<map>/ is installed to
# <INSTALL_DESTINATION>/<map>/, the layout
# rmf_demos_maps uses (share/<package>/maps/<map>/nav_graphs/0.yaml, ...).
#
# The executable is MAPC_EXECUTABLE (a cache variable; found on PATH when unset).

if(CMAKE_VERSION VERSION_LESS 3.16)
  message(FATAL_ERROR "mapc.cmake needs CMake 3.16 or newer")
endif()

# Paths in depfiles are made relative to the build tree by CMake (needed by Ninja).
if(POLICY CMP0116)
  cmake_policy(SET CMP0116 NEW)
endif()

if(NOT MAPC_EXECUTABLE)
  find_program(MAPC_EXECUTABLE mapc)
endif()

function(mapc_generate_maps)
  cmake_parse_arguments(ARG "NO_INSTALL" "TARGET;OUTPUT_DIR;INSTALL_DESTINATION"
    "MAPS;TARGETS;TEXTURE_PATHS" ${ARGN})
  if(NOT ARG_TARGET)
    message(FATAL_ERROR "mapc_generate_maps: TARGET is required")
  endif()
  if(NOT ARG_MAPS)
    message(FATAL_ERROR "mapc_generate_maps: MAPS is required")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "mapc_generate_maps: unknown arguments: ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT MAPC_EXECUTABLE)
    message(FATAL_ERROR "mapc_generate_maps: mapc not found; set MAPC_EXECUTABLE")
  endif()
  if(NOT ARG_OUTPUT_DIR)
    set(ARG_OUTPUT_DIR "${CMAKE_CURRENT_BINARY_DIR}/maps")
  endif()
  if(NOT ARG_INSTALL_DESTINATION)
    set(ARG_INSTALL_DESTINATION "share/${PROJECT_NAME}/maps")
  endif()

  set(options "")
  if(ARG_TARGETS)
    string(REPLACE ";" "," targets "${ARG_TARGETS}")
    list(APPEND options --targets ${targets})
  endif()
  foreach(dir IN LISTS ARG_TEXTURE_PATHS)
    get_filename_component(dir "${dir}" ABSOLUTE)
    list(APPEND options --texture-path "${dir}")
  endforeach()

  set(use_depfile FALSE)
  if(CMAKE_GENERATOR MATCHES "Ninja")
    set(use_depfile TRUE)
  elseif(CMAKE_GENERATOR MATCHES "Makefiles" AND NOT CMAKE_VERSION VERSION_LESS 3.20)
    set(use_depfile TRUE)
  elseif(NOT CMAKE_VERSION VERSION_LESS 3.21)
    set(use_depfile TRUE)
  endif()

  set(stamp_dir "${CMAKE_CURRENT_BINARY_DIR}/mapc_${ARG_TARGET}")
  set(stamps "")
  foreach(map IN LISTS ARG_MAPS)
    get_filename_component(map "${map}" ABSOLUTE)
    get_filename_component(file_name "${map}" NAME)
    # The map's name as mapc derives it: less `.building.yaml` (or the last extension).
    if(file_name MATCHES "^(.+)\\.((building|project)\\.yaml|site\\.json)$")
      set(name "${CMAKE_MATCH_1}")
    else()
      get_filename_component(name "${map}" NAME_WLE)
    endif()
    set(stamp "${stamp_dir}/${name}.stamp")
    set(depfile "${stamp_dir}/${name}.d")
    set(depends "${map}")
    if(IS_ABSOLUTE "${MAPC_EXECUTABLE}")
      list(APPEND depends "${MAPC_EXECUTABLE}")
    endif()
    set(depfile_args "")
    if(use_depfile)
      set(depfile_args DEPFILE "${depfile}")
    endif()
    add_custom_command(
      OUTPUT "${stamp}"
      COMMAND "${MAPC_EXECUTABLE}" build "${map}" -o "${ARG_OUTPUT_DIR}"
              --stamp "${stamp}" --depfile "${depfile}" ${options}
      DEPENDS ${depends}
      ${depfile_args}
      COMMENT "mapc: generating map ${name}"
      VERBATIM)
    list(APPEND stamps "${stamp}")
    if(NOT ARG_NO_INSTALL)
      # mapc's manifest (what it wrote, for pruning stale files) is not part of the map.
      install(DIRECTORY "${ARG_OUTPUT_DIR}/${name}/"
              DESTINATION "${ARG_INSTALL_DESTINATION}/${name}"
              PATTERN ".mapc-manifest*" EXCLUDE)
    endif()
  endforeach()
  add_custom_target(${ARG_TARGET} ALL DEPENDS ${stamps})
endfunction()
