#pragma once
// Move-only owners of GL objects, one type per object kind, all created with GL 4.5 DSA calls.
// A default-constructed object is empty (id 0) and its destructor does nothing; otherwise the
// destructor deletes the GL object, so it must run while the owning context is current.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <utility>

#include "gl/gl_api.h"

namespace tc::gl {

// One template over a Traits type with `static GLuint create(args...)` and
// `static void destroy(GLuint)`; the aliases below are the names renderer code uses.
template <class Traits>
class GlObject {
public:
    GlObject() noexcept = default;
    // Takes ownership of an existing object name.
    explicit GlObject(GLuint id) noexcept : m_id(id) {}
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;
    GlObject(GlObject&& other) noexcept : m_id(other.release()) {}
    GlObject& operator=(GlObject&& other) noexcept {
        if (this != &other) reset(other.release());
        return *this;
    }
    ~GlObject() { reset(); }

    // Creates a new object: Buffer::create(), Texture::create(GL_TEXTURE_2D), ...
    template <class... Args>
    static GlObject create(Args... args) {
        return GlObject(Traits::create(args...));
    }

    GLuint id() const noexcept { return m_id; }
    bool empty() const noexcept { return m_id == 0; }
    explicit operator bool() const noexcept { return m_id != 0; }

    // Gives up ownership without deleting; the object is empty afterwards.
    GLuint release() noexcept { return std::exchange(m_id, 0); }
    // Deletes the owned object (if any) and takes `id` instead.
    void reset(GLuint id = 0) noexcept {
        if (m_id) Traits::destroy(m_id);
        m_id = id;
    }

private:
    GLuint m_id = 0;
};

namespace detail {
struct BufferTraits {
    static GLuint create() {
        GLuint id = 0;
        glCreateBuffers(1, &id);
        return id;
    }
    static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
    static GLuint create(GLenum target) {
        GLuint id = 0;
        glCreateTextures(target, 1, &id);
        return id;
    }
    static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
    static GLuint create() {
        GLuint id = 0;
        glCreateFramebuffers(1, &id);
        return id;
    }
    static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct ProgramTraits {
    static GLuint create() { return glCreateProgram(); }
    static void destroy(GLuint id) { glDeleteProgram(id); }
};
struct ShaderTraits {
    static GLuint create(GLenum type) { return glCreateShader(type); }
    static void destroy(GLuint id) { glDeleteShader(id); }
};
struct QueryTraits {
    static GLuint create(GLenum target) {
        GLuint id = 0;
        glCreateQueries(target, 1, &id);
        return id;
    }
    static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct VertexArrayTraits {
    static GLuint create() {
        GLuint id = 0;
        glCreateVertexArrays(1, &id);
        return id;
    }
    static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
}  // namespace detail

using Buffer = GlObject<detail::BufferTraits>;            // Buffer::create()
using Texture = GlObject<detail::TextureTraits>;          // Texture::create(GL_TEXTURE_2D)
using Framebuffer = GlObject<detail::FramebufferTraits>;  // Framebuffer::create()
using Program = GlObject<detail::ProgramTraits>;          // Program::create()
using Shader = GlObject<detail::ShaderTraits>;            // Shader::create(GL_FRAGMENT_SHADER)
using Query = GlObject<detail::QueryTraits>;              // Query::create(GL_TIMESTAMP)
using VertexArray = GlObject<detail::VertexArrayTraits>;  // VertexArray::create()

// Immutable storage (glNamedBufferStorage) of `bytes` bytes, initialised from `data` if not null;
// `flags` as for glNamedBufferStorage (GL_DYNAMIC_STORAGE_BIT, GL_MAP_READ_BIT, ...). GL rejects
// zero-sized storage, so `bytes == 0` allocates 4 bytes: empty inputs need no special case.
Buffer makeBuffer(std::size_t bytes, const void* data = nullptr, GLbitfield flags = 0);
// A buffer texture (GL_TEXTURE_BUFFER) over `buffer`, read as `internalFormat` texels (texelFetch on
// a samplerBuffer / usamplerBuffer); the buffer must outlive it.
Texture makeBufferTexture(const Buffer& buffer, GLenum internalFormat);

// A single-level 2D texture with immutable storage (glTextureStorage2D), nearest filtering and
// clamp-to-edge wrapping: render targets and lookup tables are read texel-exact.
Texture makeTexture2D(GLenum internalFormat, int width, int height);

// How a 3D volume texture is sampled: trilinear (and between mip levels with `mipmapped`); outside
// the grid either zero (ZeroBorder: a density volume is empty outside its grid) or the border
// voxels' values (ClampToEdge: a lookup table over the grid).
enum class VolumeEdge { ZeroBorder, ClampToEdge };
void setVolumeSampling(GLuint texture, bool mipmapped, VolumeEdge edge);

// Bytes of storage makeBuffer and makeTexture2D have allocated in this process so far (never
// decreases): tests measure what a technique allocates per pixel of its target with it.
std::uint64_t allocatedStorageBytes();

// A framebuffer drawing to `colors` (attachments 0, 1, ... in order, all set as draw buffers)
// and, if not null, the depth texture `depth`; checked for completeness (naming `what`).
Framebuffer makeFramebuffer(std::initializer_list<const Texture*> colors, const Texture* depth, const char* what);

// Throws tc::Error(ExitCode::Internal) naming `what` and the status (GL_FRAMEBUFFER_INCOMPLETE_*)
// unless the framebuffer is complete. Call once after attaching, not per frame.
void checkFramebuffer(const Framebuffer& framebuffer, const char* what);

}  // namespace tc::gl
