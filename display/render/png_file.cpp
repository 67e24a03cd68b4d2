// PNG output for screenshots: stb_image_write (libstb-dev) into a temp file in the target folder,
// renamed over the target only when complete, so a failed write loses nothing.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "display/render/renderer.hpp"

namespace kerf::render {

Status<RenderError> write_png(const std::string& path, int width, int height,
                              const std::vector<std::uint8_t>& rgba) {
    if (width < 1 || height < 1 ||
        rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        return Err{RenderError{RenderErrc::kBadOption, "screenshot " + path,
                               "pixel buffer does not match " + std::to_string(width) + "x" +
                                   std::to_string(height) + " RGBA"}};
    }
    const std::string tmp = path + ".tmp" + std::to_string(::getpid());
    if (!stbi_write_png(tmp.c_str(), width, height, 4, rgba.data(), width * 4)) {
        const int err = errno;
        std::remove(tmp.c_str());
        return Err{RenderError{RenderErrc::kIo, "screenshot " + path,
                               "cannot write '" + tmp + "'" +
                                   (err ? std::string(": ") + std::strerror(err) : std::string())}};
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::remove(tmp.c_str());
        return Err{RenderError{RenderErrc::kIo, "screenshot " + path,
                               std::string("rename failed: ") + std::strerror(err)}};
    }
    return {};
}

}  // namespace kerf::render
