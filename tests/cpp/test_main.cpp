// Runs every TEST of the files linked with it; arguments select tests by name substring.
#include "test_driver.hpp"

int main(int argc, char** argv) { return test_driver::run_all(argc, argv); }
