#include "core/mosaic/frame_warper.h"

#include <algorithm>
#include <cmath>

#include "core/mosaic/mapping_grid.h"

namespace seamap {

FrameWarper::FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size,
                         const WarpOptions& options, std::shared_ptr<const HeightGrid> surface)
    : projection_(camera, frame, zoom, tile_size), shape_(camera), feather_(options.feather_power), options_(options) {
  if (surface) {
    surface_ = std::make_unique<SurfaceProjection>(projection_, std::move(surface));
    options_.grid_step = options_.surface_grid_step;
    shape_.by_slant = options_.nadir_seams;  // over relief the most nadir view keeps a pixel
  }
  options_.grid_step = std::clamp(options_.grid_step, 1, kMaxGridStep);
}

std::optional<SeabedProjection::MapOutline> FrameWarper::Outline(const VehiclePose& pose) const {
  return surface_ ? surface_->Outline(pose) : projection_.Outline(pose);
}

std::optional<WarpedFrame> FrameWarper::Warp(const cv::Mat& image, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours) const {
  return Warp([&image](int, int) -> const cv::Mat& { return image; }, pose, neighbours);
}

std::optional<WarpedFrame> FrameWarper::Warp(const RowSource& rows, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours) const {
  // 1. Map: the frame's box, and how its pixels map to this frame's and the
  // neighbours' raw images (through the plane, or the surface).
  const auto outline = Outline(pose);
  if (!outline) return std::nullopt;
  WarpedFrame out;
  out.box_x0 = outline->box[0];
  out.box_y0 = outline->box[1];
  const int width = out.box_width = static_cast<int>(outline->box[2]);
  const int height = out.box_height = static_cast<int>(outline->box[3]);
  std::vector<std::unique_ptr<BoxMapping>> maps;  // this frame's, then the neighbours' that see the seabed
  if (surface_) {
    std::vector<VehiclePose> views{pose};
    for (const VehiclePose& n : neighbours)
      if (options_.seam_band > 0 && views.size() < 1 + kMaxNeighbours && projection_.SeesSeabed(n)) views.push_back(n);
    maps = surface_->Mappings(*outline, views);
  } else {
    maps.push_back(
        std::make_unique<PlaneMapping>(projection_, projection_.CameraFromBox(*outline, out.box_x0, out.box_y0)));
    for (const VehiclePose& n : neighbours) {
      if (options_.seam_band <= 0 || maps.size() == 1 + kMaxNeighbours) break;
      const auto other = projection_.Outline(n);
      if (other)
        maps.push_back(
            std::make_unique<PlaneMapping>(projection_, projection_.CameraFromBox(*other, out.box_x0, out.box_y0)));
    }
  }
  // Each neighbour's seam spans the same share of the spacing at any
  // overlap: the spacing is how centrally the neighbour sees this frame's centre.
  std::vector<const BoxMapping*> neighbour_maps;
  float inv_seam[kMaxNeighbours] = {1, 1};
  const cv::Point2d centre(outline->centre.x - out.box_x0, outline->centre.y - out.box_y0);
  const RawPosition own_centre = maps[0]->ToRaw(centre.x, centre.y);
  for (size_t k = 1; k < maps.size(); ++k) {
    const RawPosition c = maps[k]->ToRaw(centre.x, centre.y);
    inv_seam[neighbour_maps.size()] =
        InverseSeamWidth(options_.seam_band, c.valid ? shape_.Spacing(c.u, c.v, c.slant, own_centre.slant) : 1.0f);
    neighbour_maps.push_back(maps[k].get());
  }
  const MappingGrid grid(*maps[0], shape_, neighbour_maps, inv_seam, width, height, options_.grid_step);

  // 2. Weigh, onto this thread's canvas.
  PaintCanvas canvas(width, height, options_.channels);
  thread_local std::vector<KeptRow> kept;
  kept.clear();
  const std::array<int, 2> raw_rows =
      Weigh(grid, static_cast<int>(neighbour_maps.size()), inv_seam, width, height, &canvas, &kept);
  // 3. Sample: only now is it known which raw rows are needed.
  if (raw_rows[0] <= raw_rows[1]) Sample(rows(raw_rows[0], raw_rows[1]), kept, &canvas);
  // 4. Cut.
  canvas.CutInto(out.box_x0, out.box_y0, &out);
  return out;
}

std::array<int, 2> FrameWarper::Weigh(const MappingGrid& grid, int neighbours, const float* inv_seam, int box_width,
                                      int box_height, PaintCanvas* canvas, std::vector<KeptRow>* kept) const {
  const int step = grid.step();
  float v_min = 1e30f, v_max = -1e30f;
  alignas(16) float w[kMaxGridStep + 4];
  for (int by = 0; by < grid.blocks_y(); ++by) {
    for (int bx = 0; bx < grid.blocks_x(); ++bx) {
      if (!grid.MayKeepBlock(bx, by)) continue;
      const MappingGrid::Block block = grid.BlockAt(bx, by);
      const int x0 = bx * step, y0 = by * step;
      const int cols = std::min(step, box_width - x0), rows = std::min(step, box_height - y0);
      for (int j = 0; j < rows; ++j) {
        const BlockRow r = block.Row(j);
        if (!grid.MayKeepRow(r)) continue;
        RowWeights(options_.kernels, shape_, feather_, r, neighbours, inv_seam, cols, w);
        const uint64_t mask = ToCanvasWeights(options_.kernels, w, cols, canvas->Weights(y0 + j) + x0);
        if (!mask) continue;
        const int i0 = __builtin_ctzll(mask), i1 = 63 - __builtin_clzll(mask);
        canvas->AddRun(y0 + j, x0 + i0, x0 + i1);
        // v is linear along the row, so its ends bound the raw rows it samples.
        const float va = r.V(static_cast<float>(i0)), vb = r.V(static_cast<float>(i1));
        v_min = std::min(v_min, std::min(va, vb));
        v_max = std::max(v_max, std::max(va, vb));
        kept->push_back({x0, y0 + j, mask, r.u0, r.du, r.v0, r.dv});
      }
    }
  }
  if (kept->empty()) return {0, -1};
  // Bilinear: a pixel at v samples rows floor(v) and floor(v) + 1; one to spare each side.
  return {static_cast<int>(std::floor(v_min)) - 1, static_cast<int>(std::ceil(v_max)) + 1};
}

void FrameWarper::Sample(const cv::Mat& image, const std::vector<KeptRow>& kept, PaintCanvas* canvas) const {
  const RawImage raw{image.ptr<uint8_t>(), image.step[0], image.cols, image.rows, options_.channels};
  for (const KeptRow& k : kept) {
    BlockRow r;
    r.u0 = k.u0;
    r.du = k.du;
    r.v0 = k.v0;
    r.dv = k.dv;
    SampleRow(options_.kernels, raw, r, k.mask, canvas->Pixels(k.y) + k.x * options_.channels);
  }
}

}  // namespace seamap
