# The C# sample (bindings/csharp/samples/Fig3Cut.cs) run under mono and checked against the CLI:
#  - the sample's own checks pass (faces updated from the change, exceptions, no managed
#    allocation over FRAMES frames);
#  - its re-posed OBJ equals, byte for byte, the CLI posing its glTF with the same edits;
#  - its cut reports the counts the CLI's `cut --json` reports for the same plane and pose;
#  - its glTF passes the Khronos validator (node, when the oracles are installed).
# Arguments: -DMONO= -DEXE= -DLIBDIR= -DCLI= -DMODEL= -DWORK= -DNODE= -DVALIDATOR=
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${LIBDIR} ${MONO} ${EXE} ${MODEL} ${WORK} 10000
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the C# sample failed (${status})")
endif()

set(edits --set "nodes[14]:rotate=0,1,1,40.1" --set "nodes[14]:translate=0.1,0,0" --set "nodes[14]:scale=0.5"
          --set "nodes[15]:rotate=0,1,1,17.2")
execute_process(COMMAND ${CLI} pose ${WORK}/cesium_cut.glb --time 0.5 ${edits} -o ${WORK}/cli_reposed.obj
                RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "cgamesh pose failed: ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/cesium_cut_reposed.obj ${WORK}/cli_reposed.obj
                RESULT_VARIABLE differ)
if(NOT differ EQUAL 0)
  message(FATAL_ERROR "the C# re-posed OBJ differs from the CLI's pose of the C# glTF")
endif()

execute_process(COMMAND ${CLI} cut ${MODEL} --time 0.5 --plane 0,1,0,0.9 -o ${WORK}/cli_cut.glb --json
                RESULT_VARIABLE status OUTPUT_VARIABLE cli_json ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "cgamesh cut failed: ${err}")
endif()
file(READ ${WORK}/cut.json sample_json)
foreach(key intersection_points faces_in faces_split)
  string(JSON a GET "${cli_json}" ${key})
  string(JSON b GET "${sample_json}" ${key})
  if(NOT a EQUAL b)
    message(FATAL_ERROR "${key}: the CLI's cut reports ${a}, the C# cut ${b}")
  endif()
endforeach()
# Both pieces in one mesh here, two meshes there: the same faces in all.
string(JSON faces_a GET "${cli_json}" faces_out 0)
string(JSON faces_b GET "${cli_json}" faces_out 1)
string(JSON faces_c GET "${sample_json}" faces_out)
math(EXPR faces_cli "${faces_a} + ${faces_b}")
if(NOT faces_cli EQUAL faces_c)
  message(FATAL_ERROR "faces after the cut: the CLI ${faces_cli}, C# ${faces_c}")
endif()

if(NODE AND EXISTS ${VALIDATOR})
  execute_process(COMMAND ${NODE} ${VALIDATOR} ${WORK}/cesium_cut.glb RESULT_VARIABLE status OUTPUT_VARIABLE log
                  ERROR_VARIABLE log)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "the C# glTF does not validate:\n${log}")
  endif()
endif()
