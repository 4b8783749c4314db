#include "map/covisibility_graph.h"

#include <deque>
#include <set>

namespace ldsm {

void CovisibilityGraph::connect(int a, int b, int weight) {
  if (a == b) return;
  edges_[a][b] += weight;
  edges_[b][a] += weight;
}

void CovisibilityGraph::remove(int id) {
  const auto it = edges_.find(id);
  if (it == edges_.end()) return;
  for (const auto& [other, w] : it->second) {
    const auto o = edges_.find(other);
    if (o != edges_.end()) o->second.erase(id);
  }
  edges_.erase(it);
}

std::vector<int> CovisibilityGraph::neighbourhood(const std::vector<int>& start, int hops,
                                                  std::size_t max_count) const {
  std::set<int> seen(start.begin(), start.end());
  std::deque<std::pair<int, int>> queue;  // (id, depth)
  for (const int s : start) queue.emplace_back(s, 0);
  std::vector<int> out;
  while (!queue.empty() && out.size() < max_count) {
    const auto [id, depth] = queue.front();
    queue.pop_front();
    if (depth >= hops) continue;
    const auto it = edges_.find(id);
    if (it == edges_.end()) continue;
    for (const auto& [other, w] : it->second) {
      if (!seen.insert(other).second) continue;
      out.push_back(other);
      if (out.size() >= max_count) break;
      queue.emplace_back(other, depth + 1);
    }
  }
  return out;
}

int CovisibilityGraph::weight(int a, int b) const {
  const auto it = edges_.find(a);
  if (it == edges_.end()) return 0;
  const auto jt = it->second.find(b);
  return jt == it->second.end() ? 0 : jt->second;
}

std::size_t CovisibilityGraph::edgeCount() const {
  std::size_t n = 0;
  for (const auto& [id, e] : edges_) n += e.size();
  return n / 2;
}

std::vector<std::array<int, 3>> CovisibilityGraph::edges() const {
  std::vector<std::array<int, 3>> out;
  for (const auto& [a, neighbours] : edges_)
    for (const auto& [b, w] : neighbours)
      if (a < b) out.push_back({a, b, w});
  return out;
}

}  // namespace ldsm
