# ldsm_add_library(<name> EXPORT_NAME <n> PUBLIC_DEPS ... PRIVATE_DEPS ...)
# A static library from every .cpp under src/ of the calling folder, public headers in include/.
function(ldsm_add_library name)
  cmake_parse_arguments(ARG "" "EXPORT_NAME" "PUBLIC_DEPS;PRIVATE_DEPS;EXCLUDE_REGEX" ${ARGN})
  file(GLOB_RECURSE srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  foreach(rx IN LISTS ARG_EXCLUDE_REGEX)
    list(FILTER srcs EXCLUDE REGEX "${rx}")
  endforeach()
  add_library(${name} ${srcs})
  add_library(ldsm::${ARG_EXPORT_NAME} ALIAS ${name})
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${ARG_EXPORT_NAME} OUTPUT_NAME ${name})
  target_include_directories(${name}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
           $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS}
                        $<BUILD_INTERFACE:ldsm_build_flags>)
  install(TARGETS ${name} EXPORT ldsmTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
