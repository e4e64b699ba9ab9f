// CGAL Optimal Transportation Curve Reconstruction (de Goes et al. 2011) as a peer for
// benchmarks/bench_peers.py.
//
//   otr2 POINTS_FILE TARGET [TARGET ...]
//
// POINTS_FILE holds one "x y" pair per line. The targets are vertex counts in decreasing
// order; OTR2 is a decimation, so one run visits them all: after run_until(target) the
// current output is written as
//
//   T target n_points n_isolated n_segments seconds_since_start
//   x y            (n_points lines: every output vertex)
//   i              (n_isolated lines: indices of isolated vertices)
//   a b            (n_segments lines: vertex indices of each segment)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Optimal_transportation_reconstruction_2.h>
#include <CGAL/Real_timer.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_2 Point;
typedef CGAL::Optimal_transportation_reconstruction_2<K> Otr2;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: otr2 POINTS_FILE TARGET [TARGET ...]\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "otr2: cannot read %s\n", argv[1]);
    return 2;
  }
  std::vector<Point> points;
  double x, y;
  while (in >> x >> y) points.emplace_back(x, y);
  if (points.size() < 3) {
    std::fprintf(stderr, "otr2: need at least 3 points, got %zu\n", points.size());
    return 2;
  }

  CGAL::Real_timer timer;
  timer.start();
  Otr2 otr2(points);
  for (int k = 2; k < argc; ++k) {
    std::size_t target = std::strtoul(argv[k], nullptr, 10);
    otr2.run_until(target);
    std::vector<Point> vertices;
    std::vector<std::size_t> isolated;
    std::vector<std::pair<std::size_t, std::size_t>> segments;
    otr2.indexed_output(std::back_inserter(vertices), std::back_inserter(isolated),
                        std::back_inserter(segments));
    std::printf("T %zu %zu %zu %zu %.6f\n", target, vertices.size(), isolated.size(),
                segments.size(), timer.time());
    for (const Point& p : vertices) std::printf("%.17g %.17g\n", p.x(), p.y());
    for (std::size_t i : isolated) std::printf("%zu\n", i);
    for (const auto& s : segments) std::printf("%zu %zu\n", s.first, s.second);
  }
  return 0;
}
