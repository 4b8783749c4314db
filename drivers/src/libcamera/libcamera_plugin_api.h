// The C interface between ldsm_drivers and the libcamera plugin (libldsm_libcamera_plugin.so,
// built from drivers/libcamera_plugin/ when libcamera is found). The plugin holds everything that
// links libcamera (and its GnuTLS, LTTng, udev dependencies), so that only processes that open a
// libcamera camera load them. Plain C types only: no exception or C++ object crosses it.
#pragma once

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LDSM_LIBCAMERA_PLUGIN_ABI_VERSION 1
#define LDSM_LIBCAMERA_PLUGIN_ENTRY "ldsm_libcamera_plugin_v1"
#define LDSM_LIBCAMERA_PLUGIN_FILE "libldsm_libcamera_plugin.so"

/// An open, started camera (opaque; owned by the plugin).
typedef struct LdsmCamera LdsmCamera;

/// What to open. Formats are libcamera PixelFormats (fourcc + modifier) in order of preference.
typedef struct LdsmCameraSettings {
  const char* camera_id; /* NULL or "": the first camera */
  int raw;               /* 1: StreamRole::Raw, 0: StreamRole::VideoRecording */
  const uint32_t* fourccs;
  const uint64_t* modifiers;
  int format_count;
  int width; /* 0: the stream's default */
  int height;
  int buffer_count;
  int ae_enable;
  int32_t exposure_time_us;  /* <= 0: not set */
  float analogue_gain;       /* <= 0: not set */
  int64_t frame_duration_us; /* <= 0: not set */
} LdsmCameraSettings;

/// The configured stream.
typedef struct LdsmCameraStream {
  uint32_t fourcc;
  uint64_t modifier;
  int width;
  int height;
  int stride; /* bytes between rows of plane 0 */
  char camera_id[256];
} LdsmCameraStream;

/// A completed frame, valid until the next call on its camera.
typedef struct LdsmCameraFrame {
  const unsigned char* data; /* plane 0 */
  size_t size;               /* bytes used in plane 0 */
  int64_t timestamp_ns;      /* SensorTimestamp, else the buffer's timestamp */
  int64_t exposure_time_us;  /* ExposureTime metadata; <= 0 when not reported */
  double analogue_gain;      /* AnalogueGain metadata; <= 0 when not reported */
  uint32_t sequence;
} LdsmCameraFrame;

typedef struct LdsmLibcameraPlugin {
  int abi_version; /* LDSM_LIBCAMERA_PLUGIN_ABI_VERSION */
  const char* description;
  /* Camera ids separated by '\n' into `ids` (always terminated): the number of cameras, or -1
   * with a message in `error`. */
  int (*list)(char* ids, size_t ids_size, char* error, size_t error_size);
  /* Opens, configures and starts a camera: NULL on failure with a message in `error`. */
  LdsmCamera* (*open)(const LdsmCameraSettings* settings, LdsmCameraStream* stream, char* error,
                      size_t error_size);
  void (*close)(LdsmCamera* camera);
  /* Waits at most timeout_ms for the next frame: 1 when `frame` is filled, 0 on timeout, -1 on
   * error (disconnected camera...) with a message in `error`. */
  int (*next)(LdsmCamera* camera, int timeout_ms, LdsmCameraFrame* frame, char* error,
              size_t error_size);
} LdsmLibcameraPlugin;

typedef const LdsmLibcameraPlugin* (*LdsmLibcameraPluginEntry)(void);

#ifdef __cplusplus
}
#endif
