# Included by test/CMakeLists.txt: the file readers' tests in ordinary builds.
if(NOT TARGET pcl_spherical_meshless_surface)
  return()
endif()

# Broken input files (cut, lying headers, random bytes) through the reconstruction
# CLI: a one-line error, never a signal.
add_executable(test_cli_inputs ${CMAKE_CURRENT_LIST_DIR}/test_cli_inputs.cpp)
target_link_libraries(test_cli_inputs PRIVATE GTest::gtest GTest::gtest_main)
target_compile_definitions(test_cli_inputs PRIVATE
  MESHLESS_CLI="$<TARGET_FILE:pcl_spherical_meshless_surface>"
  MESHLESS_READERS_CORPUS="${CMAKE_CURRENT_LIST_DIR}/corpus_readers")
add_dependencies(test_cli_inputs pcl_spherical_meshless_surface)
gtest_discover_tests(test_cli_inputs DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)

# fuzz_readers' checks on its seed corpus without libFuzzer.
add_executable(test_fuzz_readers_corpus ${CMAKE_CURRENT_LIST_DIR}/fuzz_readers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/replay_corpus.cpp)
target_link_libraries(test_fuzz_readers_corpus PRIVATE meshless_tools)
add_test(NAME fuzz_readers_corpus_replay
  COMMAND test_fuzz_readers_corpus ${CMAKE_CURRENT_LIST_DIR}/corpus_readers)
