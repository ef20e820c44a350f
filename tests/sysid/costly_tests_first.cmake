# Included by ctest after the discovered sysid tests (tests/sysid/CMakeLists.txt): the worker-thread
# refit test runs five model selections, two minutes under the sanitizers, the longest test there.
set_tests_properties(
  "OnlineIdentifier.ScheduledRefitsAreDeterministicAndCloseWithOdonataFitsModel"
  PROPERTIES COST 1000)
