// The object that carries the test programs' precompiled header (tests/CMakeLists.txt,
// poise_test_pch): GoogleTest and the heaviest third-party headers, parsed once for every
// test program instead of once each. Nothing else: the tests' own includes stay in their files.
