/*
 * oiio_image.cpp - decoding uploaded images and encoding PNG/JPEG frames with
 * OpenImageIO. The project's one C++ file.
 *
 * BOUNDARY: the three extern "C" functions at the bottom are the only entry points.
 * Each runs its implementation inside try/catch(...) so no exception ever crosses into
 * C; an exception becomes a struct err (std::bad_alloc -> REFRACT_E_OUT_OF_MEMORY).
 * Everything the implementations own is held by RAII (unique_ptr, vector, TempFile),
 * so an exception leaks nothing.
 *
 * Decoding accepts exactly four formats, recognised by their first bytes, never by a
 * name or a Content-Type: OpenEXR (76 2f 31 01), Radiance RGBE ("#?RADIANCE" or
 * "#?RGBE"), PNG (89 'PNG' 0d 0a 1a 0a) and JPEG (ff d8 ff). The reader for that format
 * is created by name, so OIIO never guesses among its other plugins (TIFF, DICOM,
 * FFmpeg, ...), which keeps the attack surface of an upload to four parsers.
 *
 * Memory: bytes reach OIIO through an IOMemReader ioproxy and frames leave through an
 * IOVecOutput, when the plugin supports("ioproxy") (all four do in OIIO 2.4.7).
 * Otherwise the bytes go through a private temporary file (mkstemp in $TMPDIR or /tmp,
 * mode 0600), unlinked before return. io_image_test_force_tempfile() forces that path
 * so the tests cover it.
 *
 * Alpha stays unassociated (OIIO is asked not to premultiply PNG colour by alpha) and
 * is never sRGB-decoded.
 *
 * Not here: colour management beyond "PNG and JPEG are sRGB" (PNG gAMA/iCCP chunks are
 * ignored), EXIF orientation (a rotated JPEG decodes as stored), multi-part or deep EXR
 * (the first part is read; deep is rejected).
 */
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <unistd.h>

extern "C" {
#include "io_image.h"
}

namespace
{

/* Per thread, so a test that forces the fallback cannot affect another thread. */
thread_local bool force_tempfile = false;

struct ImageFormat {
    const char *name;   /* for messages */
    const char *plugin; /* OIIO's format name */
    const char *ext;    /* the file name we give OIIO */
    bool srgb;          /* integer samples are sRGB-encoded (else linear floats) */
};

const ImageFormat FORMAT_EXR = {"OpenEXR", "openexr", "exr", false};
const ImageFormat FORMAT_HDR = {"Radiance RGBE", "hdr", "hdr", false};
const ImageFormat FORMAT_PNG = {"PNG", "png", "png", true};
const ImageFormat FORMAT_JPEG = {"JPEG", "jpeg", "jpg", true};

bool starts_with(const unsigned char *bytes, size_t len, const char *magic, size_t n)
{
    return len >= n && std::memcmp(bytes, magic, n) == 0;
}

/* The format whose signature begins bytes, or nullptr. */
const ImageFormat *detect_format(const unsigned char *bytes, size_t len)
{
    if (starts_with(bytes, len, "\x76\x2f\x31\x01", 4))
        return &FORMAT_EXR;
    if (starts_with(bytes, len, "#?RADIANCE", 10) || starts_with(bytes, len, "#?RGBE", 6))
        return &FORMAT_HDR;
    if (starts_with(bytes, len, "\x89PNG\r\n\x1a\n", 8))
        return &FORMAT_PNG;
    if (starts_with(bytes, len, "\xff\xd8\xff", 3))
        return &FORMAT_JPEG;
    return nullptr;
}

/* Walks a PNG's chunks (length, type, data, CRC) up to IEND and returns why the file is
 * cut short, or "" when every chunk fits. OIIO 2.4.7's PNG reader leaks a std::string
 * each time libpng reads past the end (its read callback builds the message and
 * libpng longjmps over the destructor), so truncated uploads stop here instead; the
 * message is also clearer than libpng's. CRCs and contents are libpng's job. */
std::string png_truncation(const unsigned char *b, size_t len)
{
    size_t off = 8; /* the signature */
    for (;;) {
        if (len - off < 12)
            return "PNG is truncated: its " + std::to_string(len) +
                   " bytes end before the IEND chunk; upload the complete file";
        uint32_t n = (uint32_t)b[off] << 24 | (uint32_t)b[off + 1] << 16 |
                     (uint32_t)b[off + 2] << 8 | b[off + 3];
        std::string type;
        for (int i = 4; i < 8; i++) {
            unsigned char c = b[off + i];
            type += (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ? (char)c : '?';
        }
        if (n > 0x7fffffffu || n > len - off - 12)
            return "PNG is truncated or corrupt: chunk '" + type + "' at byte " +
                   std::to_string(off) + " claims " + std::to_string(n) + " bytes but " +
                   std::to_string(len - off - 12) + " remain; upload the complete file";
        if (type == "IEND")
            return "";
        off += 12 + (size_t)n;
    }
}

/* OIIO joins several errors with newlines; a message is one line. */
std::string one_line(std::string s)
{
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    for (char &c : s) {
        if (c == '\n')
            c = ' ';
    }
    return s.empty() ? std::string("no detail from OpenImageIO") : s;
}

/* A private temporary file, unlinked when this goes out of scope. */
class TempFile
{
  public:
    TempFile() = default;
    TempFile(const TempFile &) = delete;
    TempFile &operator=(const TempFile &) = delete;
    ~TempFile()
    {
        if (!path_.empty())
            unlink(path_.c_str());
    }

    /* Creates the file, writes len bytes (may be 0) and closes it. */
    enum refract_code create(const void *bytes, size_t len, struct err *e)
    {
        const char *dir = std::getenv("TMPDIR");
        std::string templ = std::string(dir && *dir ? dir : "/tmp") + "/refract-io-XXXXXX";
        std::vector<char> name(templ.begin(), templ.end());
        name.push_back('\0');
        int fd = mkstemp(name.data());
        if (fd < 0)
            return err_set(e, REFRACT_E_INTERNAL,
                           "cannot create a temporary image file %s: %s; set TMPDIR to a "
                           "writable directory",
                           templ.c_str(), std::strerror(errno));
        path_ = name.data();
        const char *p = static_cast<const char *>(bytes);
        while (len > 0) {
            ssize_t n = write(fd, p, len);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0) {
                int saved = errno;
                close(fd);
                return err_set(e, REFRACT_E_INTERNAL, "cannot write temporary file %s: %s",
                               path_.c_str(), std::strerror(saved));
            }
            p += n;
            len -= (size_t)n;
        }
        close(fd);
        return REFRACT_E_OK;
    }

    /* Reads the whole file into *out. */
    enum refract_code slurp(std::vector<unsigned char> *out, struct err *e) const
    {
        std::unique_ptr<FILE, int (*)(FILE *)> f(std::fopen(path_.c_str(), "rb"), std::fclose);
        if (!f)
            return err_set(e, REFRACT_E_INTERNAL, "cannot reopen temporary file %s: %s",
                           path_.c_str(), std::strerror(errno));
        unsigned char chunk[65536];
        size_t n;
        while ((n = std::fread(chunk, 1, sizeof chunk, f.get())) > 0)
            out->insert(out->end(), chunk, chunk + n);
        if (std::ferror(f.get()))
            return err_set(e, REFRACT_E_INTERNAL, "cannot read temporary file %s", path_.c_str());
        return REFRACT_E_OK;
    }

    const std::string &path() const
    {
        return path_;
    }

  private:
    std::string path_;
};

struct FreeDeleter {
    void operator()(void *p) const
    {
        std::free(p);
    }
};
using FloatBuffer = std::unique_ptr<float, FreeDeleter>;

/* Checks the opened image's shape and the pixel limit; nothing is allocated yet. */
enum refract_code check_spec(const OIIO::ImageSpec &spec, const ImageFormat &fmt,
                             long long max_pixels, struct err *e)
{
    if (spec.deep)
        return err_set(e, REFRACT_E_INVALID_IMAGE,
                       "image: deep %s images are not supported; flatten it first", fmt.name);
    if (spec.width < 1 || spec.height < 1 || spec.depth != 1 || spec.nchannels < 1)
        return err_set(e, REFRACT_E_INVALID_IMAGE,
                       "image: %s header gives %d x %d x %d pixels with %d channels; expected a "
                       "2D image with at least one channel",
                       fmt.name, spec.width, spec.height, spec.depth, spec.nchannels);
    long long pixels = (long long)spec.width * spec.height;
    if (pixels > max_pixels)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "image: %d x %d = %lld pixels exceeds the limit of %lld pixels; scale "
                       "the image down or raise the limit (refractd --max-env-pixels)",
                       spec.width, spec.height, pixels, max_pixels);
    if ((unsigned long long)pixels > SIZE_MAX / (4 * sizeof(float)))
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "image: %lld pixels do not fit in this machine's address space", pixels);
    return REFRACT_E_OK;
}

/* 8-bit sRGB code -> linear, exactly io_srgb_decode(k / 255). */
struct Srgb8Table {
    float linear[256];
    Srgb8Table()
    {
        for (int k = 0; k < 256; k++)
            linear[k] = (float)io_srgb_decode(k / 255.0);
    }
};

/* In place: the first nch samples of each 4-float pixel become linear RGBA.
 * Colour channels of sRGB formats go through the inverse transfer function; alpha is
 * linear in every format. Grey is copied to R, G and B; missing alpha is 1. */
void to_linear_rgba(float *rgba, size_t pixels, int nch, bool srgb, bool eight_bit)
{
    static const Srgb8Table table; /* thread-safe init (C++11 magic statics) */
    int colour = nch == 2 || nch == 4 ? nch - 1 : nch;
    for (size_t i = 0; i < pixels; i++) {
        float *p = rgba + 4 * i;
        for (int c = 0; srgb && c < colour; c++) {
            float v = p[c];
            if (eight_bit)
                p[c] = table.linear[(int)std::lrint(std::fmin(std::fmax(v, 0.0f), 1.0f) * 255)];
            else
                p[c] = (float)io_srgb_decode(v);
        }
        if (nch == 1) {
            p[1] = p[0];
            p[2] = p[0];
            p[3] = 1.0f;
        } else if (nch == 2) {
            p[3] = p[1];
            p[1] = p[0];
            p[2] = p[0];
        } else if (nch == 3) {
            p[3] = 1.0f;
        }
    }
}

/* Rejects NaN and infinities, naming the first bad sample. */
enum refract_code check_finite(const float *rgba, int width, int height, struct err *e)
{
    size_t n = (size_t)width * (size_t)height * 4;
    for (size_t i = 0; i < n; i++) {
        if (!std::isfinite(rgba[i])) {
            size_t px = i / 4;
            return err_set(e, REFRACT_E_INVALID_IMAGE,
                           "image: pixel (x=%zu, y=%zu) channel %c is %s; every pixel must be "
                           "a finite number",
                           px % (size_t)width, px / (size_t)width, "RGBA"[i % 4],
                           std::isnan(rgba[i]) ? "NaN" : "infinite");
        }
    }
    return REFRACT_E_OK;
}

/* Reads the opened image's first four channels as floats into a new RGBA buffer. */
enum refract_code read_pixels(OIIO::ImageInput &in, const ImageFormat &fmt, struct io_image *out,
                              struct err *e)
{
    const OIIO::ImageSpec &spec = in.spec();
    size_t pixels = (size_t)spec.width * (size_t)spec.height;
    FloatBuffer rgba(static_cast<float *>(std::malloc(pixels * 4 * sizeof(float))));
    if (!rgba)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "image: cannot allocate %zu bytes for %d x %d RGBA floats",
                       pixels * 4 * sizeof(float), spec.width, spec.height);
    int nch = spec.nchannels < 4 ? spec.nchannels : 4;
    OIIO::stride_t xstride = 4 * sizeof(float);
    if (!in.read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, rgba.get(), xstride,
                       xstride * spec.width))
        return err_set(e, REFRACT_E_INVALID_IMAGE, "image: cannot decode %s pixels: %s", fmt.name,
                       one_line(in.geterror()).c_str());
    /* A reader may succeed yet record a complaint: libjpeg fills a truncated JPEG with
     * grey and only warns "Premature end of JPEG file". An image its decoder complained
     * about is not trusted. */
    std::string complaint = in.geterror();
    if (!complaint.empty())
        return err_set(e, REFRACT_E_INVALID_IMAGE, "image: %s decoder reported: %s", fmt.name,
                       one_line(complaint).c_str());
    to_linear_rgba(rgba.get(), pixels, nch, fmt.srgb, spec.format == OIIO::TypeUInt8);
    enum refract_code code = check_finite(rgba.get(), spec.width, spec.height, e);
    if (code != REFRACT_E_OK)
        return code;
    out->width = spec.width;
    out->height = spec.height;
    out->rgba = rgba.release();
    return REFRACT_E_OK;
}

enum refract_code decode(const void *bytes, size_t len, long long max_pixels, struct io_image *out,
                         struct err *e)
{
    const unsigned char *b = static_cast<const unsigned char *>(bytes);
    const ImageFormat *fmt = len > 0 && bytes != nullptr ? detect_format(b, len) : nullptr;
    if (fmt == nullptr) {
        std::string head = len ? "" : "none";
        for (size_t i = 0; i < len && i < 8; i++) {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%s%02x", i ? " " : "", b[i]);
            head += hex;
        }
        return err_set(e, REFRACT_E_INVALID_IMAGE,
                       "image: %zu bytes that are not OpenEXR, Radiance .hdr, PNG or JPEG "
                       "(first bytes: %s); upload one of those formats",
                       len, head.c_str());
    }
    if (fmt == &FORMAT_PNG) {
        std::string why = png_truncation(b, len);
        if (!why.empty())
            return err_set(e, REFRACT_E_INVALID_IMAGE, "image: %s", why.c_str());
    }
    /* Declared before the reader, so they outlive it: its destructor may still close
     * through the proxy. */
    OIIO::Filesystem::IOMemReader mem(bytes, len);
    TempFile tmp;
    auto in = OIIO::ImageInput::create(fmt->plugin);
    if (!in)
        return err_set(e, REFRACT_E_INTERNAL, "image: OpenImageIO has no %s reader: %s", fmt->name,
                       one_line(OIIO::geterror()).c_str());
    std::string name = std::string("upload.") + fmt->ext;
    if (!force_tempfile && in->supports("ioproxy") && in->set_ioproxy(&mem)) {
        /* name is only a label; the proxy supplies the bytes */
    } else {
        enum refract_code code = tmp.create(bytes, len, e);
        if (code != REFRACT_E_OK)
            return code;
        name = tmp.path();
    }
    /* Keep colour and alpha separate: by default OIIO premultiplies PNG colour by alpha
     * (in sRGB space, before our decode), which would darken translucent texels. */
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageSpec spec;
    if (!in->open(name, spec, config))
        return err_set(e, REFRACT_E_INVALID_IMAGE, "image: cannot decode %s: %s", fmt->name,
                       one_line(in->geterror()).c_str());
    enum refract_code code = check_spec(in->spec(), *fmt, max_pixels, e);
    if (code == REFRACT_E_OK)
        code = read_pixels(*in, *fmt, out, e);
    in->close();
    return code;
}

/* Writes RGBA8 as 8-bit RGB (alpha dropped through the pixel stride) with the named
 * OIIO plugin; compression is its "Compression" attribute or nullptr for the default. */
enum refract_code encode(const ImageFormat &fmt, const uint8_t *rgba8, int width, int height,
                         const char *compression, void **out_bytes, size_t *out_len, struct err *e)
{
    /* Declared before the writer, so they outlive it (see decode). */
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput vec(bytes);
    TempFile tmp;
    auto out = OIIO::ImageOutput::create(fmt.plugin);
    if (!out)
        return err_set(e, REFRACT_E_INTERNAL, "%s encode: OpenImageIO has no writer: %s", fmt.name,
                       one_line(OIIO::geterror()).c_str());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    if (compression != nullptr)
        spec.attribute("Compression", compression);
    /* zlib level 1 for PNG frames: on a 1920x1080 render (2-core EPYC) 70 ms instead of
     * 217 ms at OIIO's default 6 for a smooth frame (file 704 KB instead of 458 KB), and
     * 156 ms instead of 864 ms for a noisy one (+10%). Frames are encoded per request. */
    spec.attribute("png:compressionLevel", 1);

    std::string name = std::string("frame.") + fmt.ext;
    bool via_proxy = !force_tempfile && out->supports("ioproxy") && out->set_ioproxy(&vec);
    if (!via_proxy) {
        enum refract_code code = tmp.create(nullptr, 0, e);
        if (code != REFRACT_E_OK)
            return code;
        name = tmp.path();
    }
    OIIO::stride_t xstride = 4;
    bool ok = out->open(name, spec) &&
              out->write_image(OIIO::TypeDesc::UINT8, rgba8, xstride, xstride * width);
    ok = out->close() && ok; /* close() flushes; always call it */
    if (!ok)
        return err_set(e, REFRACT_E_INTERNAL, "%s encode: %s", fmt.name,
                       one_line(out->geterror()).c_str());
    if (!via_proxy) {
        enum refract_code code = tmp.slurp(&bytes, e);
        if (code != REFRACT_E_OK)
            return code;
    }
    void *copy = std::malloc(bytes.size() ? bytes.size() : 1);
    if (copy == nullptr)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s encode: cannot allocate %zu bytes", fmt.name,
                       bytes.size());
    if (!bytes.empty())
        std::memcpy(copy, bytes.data(), bytes.size());
    *out_bytes = copy;
    *out_len = bytes.size();
    return REFRACT_E_OK;
}

enum refract_code check_size(const char *what, int width, int height, struct err *e)
{
    if (width < 1 || height < 1)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s encode: image is %d x %d; both sides must be at least 1", what, width,
                       height);
    return REFRACT_E_OK;
}

/* The C boundary: an exception from anything below becomes an error value. */
template <class F> enum refract_code guarded(const char *what, struct err *e, F &&body)
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory", what);
    } catch (const std::exception &ex) {
        return err_set(e, REFRACT_E_INTERNAL, "%s: OpenImageIO threw: %s", what, ex.what());
    } catch (...) {
        return err_set(e, REFRACT_E_INTERNAL, "%s: OpenImageIO threw an unknown exception", what);
    }
}

} // namespace

extern "C" enum refract_code io_image_decode(const void *bytes, size_t len, long long max_pixels,
                                             struct io_image *out, struct err *e)
{
    out->width = 0;
    out->height = 0;
    out->rgba = nullptr;
    enum refract_code code =
        guarded("image decode", e, [&] { return decode(bytes, len, max_pixels, out, e); });
    if (code != REFRACT_E_OK)
        io_image_free(out); /* in case something threw after read_pixels filled *out */
    return code;
}

extern "C" enum refract_code io_encode_png(const uint8_t *rgba8, int width, int height,
                                           void **out_bytes, size_t *out_len, struct err *e)
{
    *out_bytes = nullptr;
    *out_len = 0;
    return guarded("PNG encode", e, [&] {
        enum refract_code code = check_size("PNG", width, height, e);
        if (code != REFRACT_E_OK)
            return code;
        return encode(FORMAT_PNG, rgba8, width, height, nullptr, out_bytes, out_len, e);
    });
}

extern "C" enum refract_code io_encode_jpeg(const uint8_t *rgba8, int width, int height,
                                            int quality, void **out_bytes, size_t *out_len,
                                            struct err *e)
{
    *out_bytes = nullptr;
    *out_len = 0;
    return guarded("JPEG encode", e, [&] {
        enum refract_code code = check_size("JPEG", width, height, e);
        if (code != REFRACT_E_OK)
            return code;
        if (quality < 1 || quality > 100)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "JPEG encode: quality is %d; expected an integer in 1..100", quality);
        std::string compression = "jpeg:" + std::to_string(quality);
        return encode(FORMAT_JPEG, rgba8, width, height, compression.c_str(), out_bytes, out_len,
                      e);
    });
}

extern "C" void io_image_test_force_tempfile(int on)
{
    force_tempfile = on != 0;
}
