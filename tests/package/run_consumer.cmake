# Installs the built library into a fresh prefix, then configures, builds and runs a consumer
# project against it. -DBUILD=<cgamesh build dir> -DSRC=<consumer source> -DWORK=<scratch dir>
# -DMODEL=<a rigged .glb>
file(REMOVE_RECURSE ${WORK})
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD};--prefix;${WORK}/prefix"
    "${CMAKE_COMMAND};-S;${SRC};-B;${WORK}/build;-DCMAKE_PREFIX_PATH=${WORK}/prefix;-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${WORK}/build"
    "${WORK}/build/consumer;${MODEL}"
    "${WORK}/build/c_consumer;${MODEL}")
  execute_process(COMMAND ${step} RESULT_VARIABLE code)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${step}")
  endif()
endforeach()
if(EXISTS ${WORK}/prefix/include/cgamesh/render)
  message(FATAL_ERROR "the renderer's headers were installed without its library")
endif()
