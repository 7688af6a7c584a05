# The library's layers as build targets.
#
# sk_module(NAME [DEPS module...] [HEADERS header...] [USES external...]) makes the object library
# sk_mod_NAME from src/NAME/*.c when that directory exists (otherwise it does nothing). Its
# sources are compiled against a generated include root, ${CMAKE_BINARY_DIR}/layers/NAME, that
# holds only
#   NAME/ and DEP/       links to src/NAME and src/DEP for the module and all its (transitive)
#                        dependencies, so "param/param_internal.h" is not found from src/mesh;
#   surfkit/X.h          links to the public headers those modules own.
# A public header include/surfkit/X.h belongs to module X when src/X exists, else to the module
# that lists X.h in HEADERS (so a header moves to its own module when that directory appears).
# A dependency on a module that does not exist (yet) stands for the module owning its header, or
# for nothing. USES names an external from SK_USE_<external> (a list of targets).
#
# After the table: sk_module_check_headers() fails the configure step when a public header has no
# owner. SK_MODULES lists the modules made, SK_MODULE_OBJECTS their objects.

set(SK_MODULES)
set(SK_MODULE_OBJECTS)
set(SK_LAYERS_DIR ${CMAKE_BINARY_DIR}/layers)

function(sk_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "DEPS;HEADERS;USES")
  if(NOT IS_DIRECTORY ${CMAKE_SOURCE_DIR}/src/${name})
    return()
  endif()

  # public headers this module owns
  set(owned)
  foreach(h ${name}.h ${arg_HEADERS})
    get_filename_component(stem ${h} NAME_WE)
    if(NOT EXISTS ${CMAKE_SOURCE_DIR}/include/surfkit/${h})
      continue()
    endif()
    if(NOT stem STREQUAL name AND IS_DIRECTORY ${CMAKE_SOURCE_DIR}/src/${stem})
      continue()   # module ${stem} exists and owns its header
    endif()
    list(APPEND owned ${h})
    set(SK_HEADER_OWNER_${h} ${name} PARENT_SCOPE)
  endforeach()

  # dependencies that exist, then the transitive closure
  set(closure ${name})
  foreach(dep ${arg_DEPS})
    if(NOT IS_DIRECTORY ${CMAKE_SOURCE_DIR}/src/${dep})
      set(dep "${SK_HEADER_OWNER_${dep}.h}")
      if(dep STREQUAL "" OR dep STREQUAL name)
        continue()
      endif()
    endif()
    if(NOT TARGET sk_mod_${dep})
      message(FATAL_ERROR "sk_module(${name}): module '${dep}' must come earlier in the table")
    endif()
    list(APPEND closure ${SK_MODULE_CLOSURE_${dep}})
  endforeach()
  list(REMOVE_DUPLICATES closure)
  set(SK_MODULE_CLOSURE_${name} ${closure} PARENT_SCOPE)
  set(SK_MODULE_HEADERS_${name} ${owned} PARENT_SCOPE)

  # the include root: links to what the module may see, nothing else
  set(root ${SK_LAYERS_DIR}/${name})
  file(REMOVE_RECURSE ${root})
  file(MAKE_DIRECTORY ${root}/surfkit)
  foreach(m ${closure})
    file(CREATE_LINK ${CMAKE_SOURCE_DIR}/src/${m} ${root}/${m} SYMBOLIC)
    set(hs ${SK_MODULE_HEADERS_${m}})
    if(m STREQUAL name)
      set(hs ${owned})
    endif()
    foreach(h ${hs})
      file(CREATE_LINK ${CMAKE_SOURCE_DIR}/include/surfkit/${h} ${root}/surfkit/${h} SYMBOLIC)
    endforeach()
  endforeach()

  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${name}/*.c)
  add_library(sk_mod_${name} OBJECT ${sources})
  target_include_directories(sk_mod_${name} PRIVATE ${root})
  target_compile_options(sk_mod_${name} PRIVATE ${SK_WARNINGS})
  set_target_properties(sk_mod_${name} PROPERTIES C_VISIBILITY_PRESET hidden)
  foreach(m ${closure})
    if(NOT m STREQUAL name)
      target_link_libraries(sk_mod_${name} PRIVATE sk_mod_${m})
    endif()
  endforeach()
  foreach(u ${arg_USES})
    if(NOT DEFINED SK_USE_${u})
      message(FATAL_ERROR "sk_module(${name}): unknown external '${u}' (define SK_USE_${u})")
    endif()
    target_link_libraries(sk_mod_${name} PRIVATE ${SK_USE_${u}})
  endforeach()
  if(SK_OPENMP AND OpenMP_C_FOUND)
    target_link_libraries(sk_mod_${name} PRIVATE OpenMP::OpenMP_C)
    target_compile_definitions(sk_mod_${name} PRIVATE SK_HAVE_OPENMP=1)
  endif()

  set(SK_MODULES ${SK_MODULES} ${name} PARENT_SCOPE)
  set(SK_MODULE_OBJECTS ${SK_MODULE_OBJECTS} $<TARGET_OBJECTS:sk_mod_${name}> PARENT_SCOPE)
endfunction()

function(sk_module_check_headers)
  file(GLOB headers RELATIVE ${CMAKE_SOURCE_DIR}/include/surfkit CONFIGURE_DEPENDS
       ${CMAKE_SOURCE_DIR}/include/surfkit/*.h)
  foreach(h ${headers})
    if(NOT h STREQUAL "surfkit.h" AND "${SK_HEADER_OWNER_${h}}" STREQUAL "")
      message(FATAL_ERROR "include/surfkit/${h} belongs to no module: add it to HEADERS of its "
                          "module's sk_module() line in CMakeLists.txt")
    endif()
  endforeach()
  file(GLOB dirs LIST_DIRECTORIES true CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/*)
  foreach(d ${dirs})
    get_filename_component(m ${d} NAME)
    if(IS_DIRECTORY ${d} AND NOT m IN_LIST SK_MODULES)
      message(FATAL_ERROR "src/${m}/ has no sk_module() line in CMakeLists.txt")
    endif()
  endforeach()
endfunction()
