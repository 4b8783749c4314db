// CPU renderer of SimScene: the irradiance image an ideal pinhole camera sees from a pose.
//
// Every quad is clipped to the near plane, projected and scan-converted into an inverse-depth
// buffer (one sample per pixel); each pixel is then shaded from the nearest quad with a
// trilinear, mip-mapped lookup of its albedo pattern and detail map (footprint from the analytic
// derivatives of the plane's homography). Pixels on geometric edges (the nearest quad differs
// from a neighbour's) average 4 rotated-grid sub-samples, each taking the nearest of the quads
// seen around the pixel (sub-samples on the centre's quad reuse its value). Optional full-frame
// supersampling renders at k x k resolution and box-averages. Pixel centres are at integer
// coordinates: pixel (x, y) looks along ((x - cx) / fx, (y - cy) / fy, 1) in camera coordinates.
//
// All arithmetic is IEEE float/double in a fixed order, so results are bit-identical on every
// platform compiled with -ffp-contract=off. A renderer keeps scratch buffers: use one per thread.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/drivers/sim/det_vec.h"
#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm::drivers::sim {

struct SimRendererKernels;

struct RenderSettings {
  bool antialias_edges = true;
  int supersampling = 1;  ///< full-frame samples per axis, 1..4
};

class SimRenderer {
 public:
  /// Throws ldsm::ConfigError on an invalid camera or settings, ldsm::InputError on a scene with
  /// too many quads (65535) or missing textures.
  SimRenderer(std::shared_ptr<const SimScene> scene, const PinholeIntrinsics& camera,
              RenderSettings settings = {});

  const PinholeIntrinsics& camera() const { return camera_; }
  const SimScene& scene() const { return *scene_; }

  /// Renders the irradiance seen from camera-to-world pose `T_wc` into `irradiance` (resized to
  /// the camera size; 0 where no surface is seen). If `inverse_depth` is given it receives 1/z of
  /// the surface at each pixel centre (0 where none; the mean over samples with supersampling).
  void renderIrradiance(const Pose& T_wc, ImageF& irradiance, ImageF* inverse_depth = nullptr);
  void renderIrradiance(const RigidPose& T_wc, ImageF& irradiance, ImageF* inverse_depth = nullptr);

  /// Index of the quad seen at each pixel centre of the last render (0xffff: none), at the
  /// rendering resolution (camera size times supersampling).
  const Image<std::uint16_t>& lastQuadIds() const { return ids_; }

  /// Per-frame equations of one quad in centred pixel coordinates (xc, yc) = (x - cx, y - cy):
  /// inverse depth w = wx xc + wy yc + w0; quad coordinate u = (ux xc + uy yc + u0) / w + bu
  /// (metres), likewise v.
  struct FrameQuad {
    float w0, wx, wy;
    float u0, ux, uy, bu;
    float v0, vx, vy, bv;
    float size_u, size_v;
    float off_u, off_v;  // albedo pattern offsets (metres)
    int texture, detail;
    bool visible;
  };

 private:
  friend struct SimRendererKernels;

  struct Polygon {
    int quad;
    int count;
    double x[8], y[8];  // pixel coordinates of the near-clipped outline
  };
  struct Level {
    const float* data;  // padded: (width + 1) x (height + 1)
    std::ptrdiff_t stride;
    int width, height;
    float scale_u, scale_v;  // level texels per level-0 texel
  };
  struct TextureRef {
    bool wrap;
    float texels_per_m;
    float size_u, size_v;          // level-0 texels per row / column
    float inv_size_u, inv_size_v;  // their inverses (repeating textures)
    int count;
    Level levels[24];
  };

  void renderAt(const RigidPose& T_wc, const PinholeIntrinsics& cam, ImageF& out,
                ImageF* inverse_depth);
  void setupQuads(const RigidPose& T_wc, const PinholeIntrinsics& cam);
  void rasterize(const PinholeIntrinsics& cam);
  void shade(const PinholeIntrinsics& cam, ImageF& out);
  void antialiasEdges(const PinholeIntrinsics& cam, ImageF& out);

  std::shared_ptr<const SimScene> scene_;
  PinholeIntrinsics camera_;
  RenderSettings settings_;

  std::vector<TextureRef> textures_, details_;
  std::vector<FrameQuad> frame_quads_;   // indexed by quad id
  std::vector<Polygon> polygons_;        // projected, near-clipped outlines of visible quads
  std::vector<float> xc_;                // x - cx per column
  std::vector<std::uint8_t> edge_mask_;  // edge pixels of one row
  ImageF wbuf_;                          // inverse depth of the nearest quad
  Image<std::uint16_t> ids_;             // nearest quad
  ImageF hires_, hires_depth_;           // supersampled buffers
};

}  // namespace ldsm::drivers::sim
