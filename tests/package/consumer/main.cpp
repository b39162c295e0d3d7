// Runs tubecast's `validate` subcommand from the installed libraries and checks that the headers
// of core, io and gl (with its generated GL header) compile from include/tubecast/.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli/commands.h"
#include "core/error.h"
#include "core/scene.h"
#include "gl/gl_api.h"
#include "io/json_file.h"

int main(int argc, char** argv) {
    CLI::App app{"tubecast_consumer"};
    app.require_subcommand(1);
    tc::cli::addValidateCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const tc::Error& e) {
        std::cerr << "error: " << e.what() << "\n";
        return int(e.code());
    }
    return tc::cli::g_exitCode;
}
