// Owner of the tests' precompiled header (tests/CMakeLists.txt); it compiles nothing of its own.
