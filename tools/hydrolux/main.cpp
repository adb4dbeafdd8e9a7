// hydrolux command-line tool: parses arguments, calls the library, prints or writes results (app.cpp).
#include "common.hpp"

int main(int argc, char** argv) { return hydrolux::cli::run_cli(argc, argv); }
