// tubecast_exr_ids FILE.exr: prints the id AOV of an EXR that tubecast wrote (io/image_io.h's
// readExr), one unsigned value per pixel and line, row by row; for the MPI render tests, which
// compare it bit for bit. (oiiotool prints a uint channel normalised to [0, 1] as float, which
// does not keep the ids.) Exit 1 when the file has no id channel.
#include <iostream>

#include "io/image_io.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: tubecast_exr_ids FILE.exr\n";
        return 2;
    }
    try {
        const tc::FrameImages frame = tc::readExr(argv[1]);
        if (frame.id.empty()) {
            std::cerr << argv[1] << ": no id channel\n";
            return 1;
        }
        for (std::uint32_t id : frame.id) std::cout << id << "\n";
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
    return 0;
}
