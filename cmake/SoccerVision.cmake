# The package's build vocabulary: a library per stage, tools, and tests sorted into fast unit
# tests (scripts/test --fast) and slower integration tests.

# sv_stage_library(<stage> SOURCES ... [DEPENDS <public libs>] [PRIVATE <private libs>])
# Builds soccer_vision_<stage> from src/<stage>/, headers in include/soccer_vision/<stage>/.
function(sv_stage_library stage)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS;PRIVATE" ${ARGN})
  set(target soccer_vision_${stage})
  add_library(${target} ${A_SOURCES})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/include)
  target_link_libraries(${target} PUBLIC ${A_DEPENDS} PRIVATE ${A_PRIVATE})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  install(TARGETS ${target}
    ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
    LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
    RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endfunction()

# sv_tool(<name> SOURCES ... LIBS ...): an installed command-line program (rosrun soccer_vision <name>).
function(sv_tool name)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_link_libraries(${name} ${A_LIBS})
  add_dependencies(${name} ${PROJECT_NAME}_generate_messages_cpp)
  install(TARGETS ${name} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endfunction()

# Tests get the source tree (config files) and the tools they run as compile definitions.
function(_sv_test_setup name)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS;TOOLS" ${ARGN})
  target_link_libraries(${name} ${A_LIBS} GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test)
  target_compile_definitions(${name} PRIVATE SOCCER_VISION_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  foreach(tool ${A_TOOLS})
    string(TOUPPER ${tool} upper)
    target_compile_definitions(${name} PRIVATE ${upper}_BIN="$<TARGET_FILE:${tool}>")
    add_dependencies(${name} ${tool})
  endforeach()
endfunction()

# sv_unit_test(<name> SOURCES ... LIBS ... [TOOLS ...]): a fast gtest (seconds); run by
# scripts/test --fast (target `unit_tests`, list unit_tests.txt in the build folder) and by
# scripts/test.
set_property(GLOBAL PROPERTY SV_UNIT_TESTS "")
function(sv_unit_test name)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS;TOOLS" ${ARGN})
  catkin_add_gtest(${name} ${A_SOURCES})
  _sv_test_setup(${name} ${ARGN})
  set_property(GLOBAL APPEND PROPERTY SV_UNIT_TESTS ${name})
endfunction()

# sv_integration_test(<name> SOURCES ... LIBS ... [TOOLS ...]): a gtest over whole stages,
# rendered scenes or the tools (up to minutes); run by scripts/test only.
function(sv_integration_test name)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS;TOOLS" ${ARGN})
  catkin_add_gtest(${name} ${A_SOURCES})
  _sv_test_setup(${name} ${ARGN})
endfunction()

# sv_unit_test_script(<name> SCRIPT <file>): a fast test written as an executable script that
# takes --gtest_output=xml:FILE as the gtests do; run by scripts/test --fast and by scripts/test.
set_property(GLOBAL PROPERTY SV_UNIT_TEST_SCRIPTS "")
function(sv_unit_test_script name)
  cmake_parse_arguments(A "" "SCRIPT" "" ${ARGN})
  set(results ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/script-${name}.xml)
  catkin_run_tests_target("script" ${name} "script-${name}.xml" COMMAND "${A_SCRIPT} --gtest_output=xml:${results}")
  set_property(GLOBAL APPEND PROPERTY SV_UNIT_TEST_SCRIPTS ${A_SCRIPT})
endfunction()

# After every test is declared: the `unit_tests` target and the list scripts/test --fast runs.
function(sv_write_unit_test_list)
  get_property(tests GLOBAL PROPERTY SV_UNIT_TESTS)
  get_property(scripts GLOBAL PROPERTY SV_UNIT_TEST_SCRIPTS)
  add_custom_target(unit_tests DEPENDS ${tests})
  set(lines "")
  foreach(t ${tests})
    string(APPEND lines "$<TARGET_FILE:${t}>\n")
  endforeach()
  foreach(s ${scripts})
    string(APPEND lines "${s}\n")
  endforeach()
  file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/unit_tests.txt CONTENT "${lines}")
endfunction()
