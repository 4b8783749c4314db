// The C interface between ldsm_drivers and the video plugin (libldsm_video_plugin.so, built from
// drivers/video_plugin/). The plugin holds everything that needs OpenCV videoio, so that the
// library and the tools load videoio (and FFmpeg, GStreamer...) only when a video is opened.
// Plain C types only: no exception, allocation or C++ object crosses the boundary.
#pragma once

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/// Version of this interface; the loader refuses a plugin with another one.
#define LDSM_VIDEO_PLUGIN_ABI_VERSION 1
/// Name of the plugin's entry point, a LdsmVideoPluginEntry.
#define LDSM_VIDEO_PLUGIN_ENTRY "ldsm_video_plugin_v1"

/// An open video (opaque; owned by the plugin).
typedef struct LdsmVideo LdsmVideo;

/// A decoded frame as 8-bit grey, valid until the next call on its video.
typedef struct LdsmVideoFrame {
  const unsigned char* data;
  int width;
  int height;
  ptrdiff_t stride;   /* bytes between rows */
  double position_ms; /* decoder position after this frame (negative or NaN when unknown) */
} LdsmVideoFrame;

typedef struct LdsmVideoPlugin {
  int abi_version;         /* LDSM_VIDEO_PLUGIN_ABI_VERSION */
  const char* description; /* e.g. "OpenCV 4.6.0 videoio" */
  /* Opens a video file; NULL on failure with a message in `error` (always terminated). */
  LdsmVideo* (*open)(const char* path, char* error, size_t error_size);
  void (*close)(LdsmVideo* video);
  /* Container frame rate and frame count; 0 or negative when unknown. */
  double (*fps)(const LdsmVideo* video);
  double (*frame_count)(const LdsmVideo* video);
  /* Decodes the next frame: 1 when `frame` is filled, 0 at the end, -1 on error (`error`). */
  int (*next)(LdsmVideo* video, LdsmVideoFrame* frame, char* error, size_t error_size);
} LdsmVideoPlugin;

/// The plugin's exported entry point.
typedef const LdsmVideoPlugin* (*LdsmVideoPluginEntry)(void);

#ifdef __cplusplus
}
#endif
