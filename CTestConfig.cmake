# Where `ctest -D Experimental` (or a dashboard script) submits: ITK's CDash, as ITK's module template has it
# (InsightSoftwareConsortium/ITKModuleTemplate, {{cookiecutter.project_name}}/CTestConfig.cmake). Read only by a
# build that includes CTest's module (include(CTest)); the stand-alone build calls enable_testing() and submits nothing.
set(CTEST_PROJECT_NAME "ITK")
set(CTEST_NIGHTLY_START_TIME "1:00:00 UTC")

set(CTEST_DROP_METHOD "https")
set(CTEST_DROP_SITE "open.cdash.org")
set(CTEST_DROP_LOCATION "/submit.php?project=Insight")
set(CTEST_DROP_SITE_CDASH TRUE)
