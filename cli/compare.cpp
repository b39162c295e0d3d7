// tubecast compare A B: image difference metrics (OpenImageIO's comparison underneath).
#include <cmath>
#include <iomanip>
#include <iostream>

#include "cli/commands.h"
#include "core/error.h"
#include "io/image_io.h"

namespace tc::cli {

// Declared in cli/commands.h; compare --fail is the one subcommand that sets it.
int g_exitCode = 0;

void addCompareCommand(CLI::App& app) {
    struct Options {
        std::string a, b;
        float threshold = 1.0f / 255.0f;
        double failPsnr = 0.0;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd =
        app.add_subcommand("compare", "Compare two images: RMSE, PSNR, max error, % pixels over a threshold");
    cmd->add_option("a", options->a, "Image (PNG or EXR)")->required();
    cmd->add_option("b", options->b, "Image (PNG or EXR)")->required();
    cmd->add_option("--threshold", options->threshold,
                    "Per-channel error counted as a differing pixel (default 1/255)");
    cmd->add_option("--fail", options->failPsnr, "Exit 6 if the PSNR (dB) is below this");
    cmd->callback([options] {
        ImageDiff d = compareImages(options->a, options->b, options->threshold);
        std::cout << std::setprecision(6) << "rmse " << d.rmse << "\npsnr " << d.psnr << "\nmax_error " << d.maxError
                  << "\npixels_over_threshold_percent " << 100.0 * d.fractionOver << "\n";
        if (options->failPsnr > 0 && !(d.psnr >= options->failPsnr)) g_exitCode = int(ExitCode::ImagesDiffer);
    });
}

}  // namespace tc::cli
