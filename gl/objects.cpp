#include "gl/objects.h"

#include <atomic>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"

namespace tc::gl {

namespace {
// A relaxed counter: allocations happen on the context's thread; readers are tests.
std::atomic<std::uint64_t> g_storageBytes{0};

std::size_t bytesPerTexel(GLenum internalFormat) {
    switch (internalFormat) {
        case GL_R8:
            return 1;
        case GL_DEPTH_COMPONENT16:
            return 2;
        case GL_R32F:
        case GL_R32UI:
        case GL_RGBA8:
        case GL_DEPTH_COMPONENT32F:
            return 4;
        case GL_RG32F:
        case GL_RG32UI:
        case GL_RGBA16F:
            return 8;
        case GL_RGBA32F:
        case GL_RGBA32UI:
            return 16;
        default:
            throw Error(ExitCode::Internal, "makeTexture2D: add the size of format " + std::to_string(internalFormat));
    }
}
}  // namespace

std::uint64_t allocatedStorageBytes() {
    return g_storageBytes.load(std::memory_order_relaxed);
}

Buffer makeBuffer(std::size_t bytes, const void* data, GLbitfield flags) {
    Buffer buffer = Buffer::create();
    if (bytes == 0) {
        bytes = 4;
        data = nullptr;  // nothing to copy; the caller's pointer may be null or past-the-end
    }
    glNamedBufferStorage(buffer.id(), static_cast<GLsizeiptr>(bytes), data, flags);
    g_storageBytes.fetch_add(bytes, std::memory_order_relaxed);
    return buffer;
}

Texture makeBufferTexture(const Buffer& buffer, GLenum internalFormat) {
    Texture texture = Texture::create(GL_TEXTURE_BUFFER);
    glTextureBuffer(texture.id(), internalFormat, buffer.id());
    return texture;
}

Texture makeTexture2D(GLenum internalFormat, int width, int height) {
    TC_CHECK(width > 0 && height > 0);
    g_storageBytes.fetch_add(bytesPerTexel(internalFormat) * std::size_t(width) * std::size_t(height),
                             std::memory_order_relaxed);
    Texture texture = Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(texture.id(), 1, internalFormat, width, height);
    glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

void setVolumeSampling(GLuint texture, bool mipmapped, VolumeEdge edge) {
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, mipmapped ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    const GLint wrap = edge == VolumeEdge::ZeroBorder ? GL_CLAMP_TO_BORDER : GL_CLAMP_TO_EDGE;
    for (GLenum axis : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(texture, axis, wrap);
    if (edge == VolumeEdge::ZeroBorder) {
        const float border[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glTextureParameterfv(texture, GL_TEXTURE_BORDER_COLOR, border);
    }
}

namespace {
std::string framebufferStatusName(GLenum status) {
    switch (status) {
        case GL_FRAMEBUFFER_COMPLETE:
            return "GL_FRAMEBUFFER_COMPLETE";
        case GL_FRAMEBUFFER_UNDEFINED:
            return "GL_FRAMEBUFFER_UNDEFINED";
        case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
            return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
            return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER:
            return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
        case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER:
            return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
        case GL_FRAMEBUFFER_UNSUPPORTED:
            return "GL_FRAMEBUFFER_UNSUPPORTED";
        case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
            return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
        case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS:
            return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
        case 0:
            return "error while checking (glCheckNamedFramebufferStatus returned 0)";
        default:
            return "status 0x" + [&] {
                char hex[16];
                std::snprintf(hex, sizeof hex, "%04X", status);
                return std::string(hex);
            }();
    }
}
}  // namespace

void checkFramebuffer(const Framebuffer& framebuffer, const char* what) {
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer.id(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw Error(ExitCode::Internal,
                    std::string("framebuffer '") + what + "' is incomplete: " + framebufferStatusName(status));
}

Framebuffer makeFramebuffer(std::initializer_list<const Texture*> colors, const Texture* depth, const char* what) {
    Framebuffer framebuffer = Framebuffer::create();
    std::vector<GLenum> buffers;
    for (const Texture* color : colors) {
        const GLenum attachment = GL_COLOR_ATTACHMENT0 + GLenum(buffers.size());
        glNamedFramebufferTexture(framebuffer.id(), attachment, color->id(), 0);
        buffers.push_back(attachment);
    }
    if (depth) glNamedFramebufferTexture(framebuffer.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
    glNamedFramebufferDrawBuffers(framebuffer.id(), GLsizei(buffers.size()), buffers.data());
    checkFramebuffer(framebuffer, what);
    return framebuffer;
}

}  // namespace tc::gl
