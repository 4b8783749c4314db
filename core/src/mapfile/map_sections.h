// The sections of a version-1 map file, each written to and read from its own bytes (the tables
// of docs/map-file.md). Readers check sizes and the values that must be checked before they are
// used (unit quaternions, positive scales, flag bits); findMapProblem checks the rest.
#pragma once

#include <cstdint>
#include <vector>

#include "mapfile/byte_reader.h"
#include "mapfile/byte_writer.h"
#include "mapfile/map_data.h"

namespace ldsm::mapfile {

void writeCalibration(ByteWriter& w, const MapCalibration& c);
MapCalibration readCalibration(ByteReader& r);
/// CALR: the refinement's correction in `c` (focal_log_scale, cx_shift, cy_shift).
void writeRefinement(ByteWriter& w, const MapCalibration& c);
void readRefinement(ByteReader& r, MapCalibration& c);

void writeKeyframes(ByteWriter& w, const std::vector<KeyframeRecord>& keyframes);
std::vector<KeyframeRecord> readKeyframes(ByteReader& r);

void writeKeyframeData(ByteWriter& w, const std::vector<MarginalizedKeyframe>& data);
std::vector<MarginalizedKeyframe> readKeyframeData(ByteReader& r);

void writePoints(ByteWriter& w, const std::vector<HostedPoint>& points);
std::vector<HostedPoint> readPoints(ByteReader& r);

void writeCovisibility(ByteWriter& w, const std::vector<MapCovisibility>& edges);
std::vector<MapCovisibility> readCovisibility(ByteReader& r);

void writeGraph(ByteWriter& w, const std::vector<MapGraphEdge>& edges);
std::vector<MapGraphEdge> readGraph(ByteReader& r);

/// Bytes of each section for a map (exact), to reserve the output once.
std::size_t keyframeDataBytes(const std::vector<MarginalizedKeyframe>& data);

}  // namespace ldsm::mapfile
