# Installs the built tree into a scratch prefix, then configures, builds and runs a consumer
# project that finds it with find_package(ldsm). Run by ctest (test "package.find_package").
foreach(v BUILD_DIR WORK_DIR SOURCE_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check_package.cmake: ${v} not set")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "install failed (${rc})")
endif()
# A cross build (toolchains/, TOOLCHAIN_FILE set) configures the consumer with the same toolchain
# and sysroot, hands it ldsm_DIR (the sysroot-only package search would not look in the prefix)
# and runs it with the emulator (EMULATOR).
set(cross_args)
if(TOOLCHAIN_FILE)
  file(GLOB_RECURSE ldsm_config ${WORK_DIR}/prefix/*/ldsmConfig.cmake)
  get_filename_component(ldsm_config_dir "${ldsm_config}" DIRECTORY)
  set(cross_args -DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN_FILE} -DLDSM_SYSROOT=${SYSROOT}
                 -Dldsm_DIR=${ldsm_config_dir})
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/consumer -B ${WORK_DIR}/build
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                        ${cross_args}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "find_package(ldsm) from the installed tree failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer against ldsm::core failed (${rc})")
endif()
execute_process(COMMAND ${EMULATOR} ${WORK_DIR}/build/consumer RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "the consumer program failed (${rc})")
endif()
