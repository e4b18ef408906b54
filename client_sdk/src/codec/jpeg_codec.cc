// Colour as JPEG through libjpeg-turbo's TurboJPEG API (4:2:0, accurate DCT).
#include <turbojpeg.h>

#include "src/codec/codecs.h"

namespace omnisweep::codec {
namespace {

// TurboJPEG handles are plain pointers; this gives each one an owner.
struct TjHandle {
  tjhandle handle;
  explicit TjHandle(tjhandle h) : handle(h) {
    if (!handle) throw CodecError(error_prefix(kJpeg) + "cannot create a TurboJPEG handle");
  }
  ~TjHandle() { tjDestroy(handle); }
  TjHandle(const TjHandle&) = delete;
  TjHandle& operator=(const TjHandle&) = delete;
};

class JpegCodec final : public ColorCodec {
 public:
  explicit JpegCodec(int quality) : quality_(quality) {
    if (quality < 1 || quality > 100)
      throw CodecError(error_prefix(kJpeg) + "quality " + std::to_string(quality) +
                       " is outside 1-100");
  }
  std::string name() const override { return std::string(kJpeg); }

  Bytes encode(Rgb8View image) const override {
    if (image.empty()) throw CodecError(error_prefix(kJpeg) + "expects a non-empty image");
    const TjHandle tj(tjInitCompress());
    unsigned char* out = nullptr;
    unsigned long size = 0;
    if (tjCompress2(tj.handle, image.data(), image.width(), 0, image.height(), TJPF_RGB, &out,
                    &size, TJSAMP_420, quality_, 0) != 0) {
      const std::string why = tjGetErrorStr2(tj.handle);
      tjFree(out);
      throw CodecError(error_prefix(kJpeg) + "cannot encode: " + why);
    }
    Bytes bytes(out, out + size);
    tjFree(out);
    return bytes;
  }

  Rgb8Image decode(std::span<const std::uint8_t> payload, int width, int height) const override {
    if (payload.size() < 4 || payload[0] != 0xff || payload[1] != 0xd8)
      throw CodecError(error_prefix(kJpeg) + "not a JPEG payload");
    const TjHandle tj(tjInitDecompress());
    int w = 0, h = 0, subsampling = 0, colorspace = 0;
    if (tjDecompressHeader3(tj.handle, payload.data(), payload.size(), &w, &h, &subsampling,
                            &colorspace) != 0) {
      throw CodecError(error_prefix(kJpeg) + "bad header: " + tjGetErrorStr2(tj.handle));
    }
    if (w != width || h != height) {
      throw CodecError(error_prefix(kJpeg) + "payload is " + std::to_string(w) + "x" +
                       std::to_string(h) + ", the frame says " + std::to_string(width) + "x" +
                       std::to_string(height));
    }
    Rgb8Image image(width, height);
    // Warnings (a truncated scan, corrupt data) are errors: frames are whole or rejected.
    if (tjDecompress2(tj.handle, payload.data(), payload.size(), image.data(), width, 0, height,
                      TJPF_RGB, TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0) {
      throw CodecError(error_prefix(kJpeg) + "cannot decode: " + tjGetErrorStr2(tj.handle));
    }
    return image;
  }

 private:
  int quality_;
};

}  // namespace

std::unique_ptr<ColorCodec> make_jpeg_codec(int quality) {
  return std::make_unique<JpegCodec>(quality);
}

}  // namespace omnisweep::codec
