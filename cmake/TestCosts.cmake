# Rough run times (seconds, Release, 2 cores) of the longest tests, as each test's COST: ctest -j
# starts the costliest first. A clean clone (CI) has no Testing/Temporary/CTestCostData.txt, and
# without costs ctest runs the tests in the order they were declared, which left the longest
# (web.e2e, declared late) to finish alone at the end. Measured ones take over once ctest has run.
set(HYDROLUX_TEST_COSTS
  web.e2e=200 atmos.test_lee=90 cli.test_robustness=70 gallery.test_gallery=60
  python.test_batch=60 scatter.test_claims_renderer_medium=50 scatter.test_renderer_export=40
  python.test_notebooks=37 python.test_install=23
  python.test_bindings=21 python.test_examples=19 python.test_batch_hostile=17
  cli.test_safety=13 python.test_batch_inputs=13 atmos.test_claims_canting_rule=12
  scatter.test_claims_phase_drizzle=12 optics.test_bsdf=11 python.test_sky=10)

function(hydrolux_test_cost test)
  foreach(entry IN LISTS HYDROLUX_TEST_COSTS)
    string(REPLACE "=" ";" pair "${entry}")
    list(GET pair 0 name)
    if(name STREQUAL test)
      list(GET pair 1 seconds)
      set_tests_properties(${test} PROPERTIES COST ${seconds})
    endif()
  endforeach()
endfunction()
