// tubecast: headless batch renderer for dense line sets. main() only wires subcommands and turns
// errors into messages and exit codes (documented in README.md and --help).
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli/commands.h"
#include "cli/mpi_session.h"
#include "core/error.h"

int main(int argc, char** argv) {
    CLI::App app{"tubecast " TUBECAST_VERSION " - headless batch renderer for dense 3D line sets"};
    app.set_version_flag("--version", std::string("tubecast ") + TUBECAST_VERSION);
    app.require_subcommand(1);
    app.footer(
        "Exit codes:\n"
        "  0  success\n"
        "  1  internal error (a bug: please report it)\n"
        "  2  invalid input: command line, scene spec or dataset\n"
        "  3  no usable OpenGL backend (EGL / OSMesa)\n"
        "  4  cannot write output (directory, permissions, existing files without --overwrite/--resume)\n"
        "  5  some frames failed (render --keep-going: the others were written)\n"
        "  6  compare --fail: the images differ (PSNR below the threshold)\n");
    tc::cli::addRenderCommand(app);
    tc::cli::addValidateCommand(app);
    tc::cli::addInfoCommand(app);
    tc::cli::addCompareCommand(app);
    tc::cli::addConvertCommand(app);
    tc::cli::addPartitionCommand(app);
    tc::cli::addMergeTimingsCommand(app);
    tc::cli::addTechniquesCommand(app);
    tc::cli::addSceneCommand(app);
    tc::cli::addEncodeCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Usage errors are invalid input (exit 2), not CLI11's own codes.
        std::cerr << "error: " << e.what() << "\n(run 'tubecast --help' for usage)\n";
        return int(tc::ExitCode::InvalidInput);
    } catch (const tc::cli::RankFailure& e) {
        // render --mpi: every rank knows of the failure and rank 0 has printed the ranks' messages.
        return int(e.code());
    } catch (const tc::Error& e) {
        std::cerr << "error: " << e.what() << "\n";
        tc::cli::MpiSession::abortIfLeftAlone(int(e.code()));
        return int(e.code());
    } catch (const std::exception& e) {
        std::cerr << "internal error: " << e.what() << "\n";
        tc::cli::MpiSession::abortIfLeftAlone(int(tc::ExitCode::Internal));
        return int(tc::ExitCode::Internal);
    }
    return tc::cli::g_exitCode;
}
