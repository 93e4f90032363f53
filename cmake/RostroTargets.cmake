# Helpers that give every rostro target the same standard, warnings and include root.

# -Wno-restrict: GCC 12 reports false overlaps inside std::string concatenation at -O3
# (GCC bug 105329); the warning says nothing about our code.
set(ROSTRO_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wconversion
    -Wno-sign-conversion -Wno-restrict)

# rostro_library(<stage> SOURCES ... [DEPS ...]) defines the library rostro_<stage>.
# Headers are included as "<stage>/<file>.hpp" from the repository root.
function(rostro_library stage)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(rostro_${stage} ${ARG_SOURCES})
  add_library(rostro::${stage} ALIAS rostro_${stage})
  target_include_directories(rostro_${stage} PUBLIC "${PROJECT_SOURCE_DIR}")
  target_compile_options(rostro_${stage} PRIVATE ${ROSTRO_WARNINGS})
  target_link_libraries(rostro_${stage} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
endfunction()

# rostro_test(<name> SOURCES ... DEPS ...) defines a GoogleTest executable registered with ctest.
# Tests learn where data/ and ../shared are through compile definitions. Each test's ctest name
# starts with its stage, the tests/ subfolder it is defined in (tracking/Tracker.Occlusions...),
# so that `ctest -R '^tracking/'` runs one stage.
function(rostro_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_compile_options(${name} PRIVATE ${ROSTRO_WARNINGS})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    ROSTRO_SHARED_DIR="${ROSTRO_SHARED_DIR}" ROSTRO_DATA_DIR="${ROSTRO_DATA_DIR}"
    ROSTRO_BINARY_DIR="${PROJECT_BINARY_DIR}")
  file(RELATIVE_PATH stage "${PROJECT_SOURCE_DIR}/tests" "${CMAKE_CURRENT_SOURCE_DIR}")
  gtest_discover_tests(${name} TEST_PREFIX "${stage}/" DISCOVERY_TIMEOUT 60 PROPERTIES ENVIRONMENT
    "ROSTRO_DATA=${ROSTRO_DATA_DIR}")
endfunction()
