// A shared library that is not a suffuse plugin: it has no entry point.
extern "C" int some_unrelated_function() { return 42; }
