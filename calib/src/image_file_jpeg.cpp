// JPEG decoding with libjpeg(-turbo). libjpeg reports fatal errors through error_exit, which
// must not return: it longjmps back to the small "guarded" function that made the libjpeg call.
// Those functions hold no object with a destructor, so the jump never skips a C++ destructor.
// Warnings that mean corrupt or truncated data are errors too (libjpeg would otherwise fill the
// missing part with grey and succeed).
// clang-format off
#include <cstdio>  // jpeglib.h needs FILE and size_t first
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include <csetjmp>
#include <cstring>
#include <vector>

#include "image_file_codecs.h"

namespace ldsm::calib {
namespace {

/// libjpeg's error manager extended with the jump target and the last message. Standard layout
/// with the manager first, so libjpeg's pointer to it converts back. Trivially destructible.
struct JpegErrorState {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void onJpegError(j_common_ptr cinfo) {
  // Through void*: the object is a JpegErrorState, so its (on ARMv7 stricter, jmp_buf) alignment
  // holds; a direct cast trips -Wcast-align on 32-bit ARM.
  auto* state = static_cast<JpegErrorState*>(static_cast<void*>(cinfo->err));
  (*cinfo->err->format_message)(cinfo, state->message);
  std::longjmp(state->jump, 1);
}

bool isCorruptDataWarning(int code) {
  switch (code) {
    case JWRN_ARITH_BAD_CODE:
    case JWRN_HIT_MARKER:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_JPEG_EOF:
    case JWRN_MUST_RESYNC:
      return true;
    default:
      return false;
  }
}

/// Trace messages (level >= 0) and harmless warnings are dropped; corrupt data is fatal.
void onJpegMessage(j_common_ptr cinfo, int level) {
  if (level < 0 && isCorruptDataWarning(cinfo->err->msg_code)) onJpegError(cinfo);
}

// ---- guarded libjpeg steps: false when libjpeg failed (message in JpegErrorState) ------------

bool readHeader(j_decompress_ptr cinfo, JpegErrorState* state, const unsigned char* data,
                std::size_t size) {
  if (setjmp(state->jump)) return false;
  jpeg_create_decompress(cinfo);
  jpeg_mem_src(cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(cinfo, TRUE);
  return true;
}

bool startDecompress(j_decompress_ptr cinfo, JpegErrorState* state) {
  if (setjmp(state->jump)) return false;
  jpeg_start_decompress(cinfo);
  return true;
}

bool readScanline(j_decompress_ptr cinfo, JpegErrorState* state, JSAMPROW row) {
  JSAMPROW rows[1] = {row};
  if (setjmp(state->jump)) return false;
  if (jpeg_read_scanlines(cinfo, rows, 1) != 1) {
    std::snprintf(state->message, sizeof state->message, "no data for scanline %u",
                  cinfo->output_scanline);
    return false;
  }
  return true;
}

bool finishDecompress(j_decompress_ptr cinfo, JpegErrorState* state) {
  if (setjmp(state->jump)) return false;
  jpeg_finish_decompress(cinfo);
  return true;
}

/// Owner of a decompressor and its error state.
class JpegDecompressor {
 public:
  JpegDecompressor() {
    std::memset(&cinfo_, 0, sizeof cinfo_);
    std::memset(&state_, 0, sizeof state_);
    cinfo_.err = jpeg_std_error(&state_.manager);
    state_.manager.error_exit = onJpegError;
    state_.manager.emit_message = onJpegMessage;
  }
  ~JpegDecompressor() { jpeg_destroy_decompress(&cinfo_); }  // safe before creation (mem null)
  JpegDecompressor(const JpegDecompressor&) = delete;
  JpegDecompressor& operator=(const JpegDecompressor&) = delete;

  j_decompress_ptr cinfo() { return &cinfo_; }
  JpegErrorState* state() { return &state_; }

 private:
  jpeg_decompress_struct cinfo_;
  JpegErrorState state_;
};

const char* colourSpaceName(J_COLOR_SPACE space) {
  switch (space) {
    case JCS_CMYK:
      return "CMYK";
    case JCS_YCCK:
      return "YCCK";
    default:
      return "unknown";
  }
}

}  // namespace

namespace detail {

template <typename T>
ImageFileInfo decodeJpeg(const unsigned char* data, std::size_t size, const std::string& where,
                         Image<T>& out) {
  JpegDecompressor decompressor;
  j_decompress_ptr cinfo = decompressor.cinfo();
  JpegErrorState* state = decompressor.state();
  const auto fail = [&] { throwDecodeError(where, std::string("JPEG: ") + state->message); };

  if (!readHeader(cinfo, state, data, size)) fail();
  ImageFileInfo file;
  file.format = ImageFileFormat::Jpeg;
  file.width = static_cast<int>(cinfo->image_width);
  file.height = static_cast<int>(cinfo->image_height);
  file.channels = cinfo->num_components;
  file.bit_depth = cinfo->data_precision;
  checkImageSize(where, cinfo->image_width, cinfo->image_height);
  const J_COLOR_SPACE space = cinfo->jpeg_color_space;
  if (space != JCS_GRAYSCALE && space != JCS_YCbCr && space != JCS_RGB)
    throwDecodeError(where, std::string("JPEG: unsupported colour space ") +
                                colourSpaceName(space) + " (grey, YCbCr and RGB are supported)");
  cinfo->out_color_space = JCS_GRAYSCALE;  // luma straight from the decoder
  if (!startDecompress(cinfo, state)) fail();
  if (cinfo->output_components != 1 || static_cast<int>(cinfo->output_width) != file.width ||
      static_cast<int>(cinfo->output_height) != file.height)
    throwDecodeError(where, "JPEG: unexpected decoder output layout");

  out.resize(file.width, file.height);
  if constexpr (sizeof(T) == 1) {
    for (int y = 0; y < file.height; ++y)
      if (!readScanline(cinfo, state, reinterpret_cast<JSAMPROW>(out.row(y)))) fail();
  } else {
    std::vector<JSAMPLE> row(static_cast<std::size_t>(file.width));
    for (int y = 0; y < file.height; ++y) {
      if (!readScanline(cinfo, state, row.data())) fail();
      rowToGrey(row.data(), 8, 1, file.width, out.row(y));
    }
  }
  if (!finishDecompress(cinfo, state)) fail();
  return file;
}

template ImageFileInfo decodeJpeg(const unsigned char*, std::size_t, const std::string&, ImageU8&);
template ImageFileInfo decodeJpeg(const unsigned char*, std::size_t, const std::string&, ImageU16&);

}  // namespace detail
}  // namespace ldsm::calib
