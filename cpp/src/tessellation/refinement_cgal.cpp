// Delaunay refinement of a planar straight-line graph (curriculum §2.1.1): Ruppert's algorithm as
// our own loop on CGAL's constrained Delaunay triangulation, with Shewchuk's concentric-shell
// segment splitting and a terminating rule near small input angles.
//
// References: J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh
// generation", J. Algorithms 18 (1995); J. R. Shewchuk, "Delaunay refinement algorithms for
// triangular mesh generation", Comput. Geom. 22 (2002), §§3-6 (diametral circles, concentric
// shells, seditious edges); G. L. Miller, S. E. Pav, N. J. Walkington, "When and why Ruppert's
// algorithm works", IMR 2003 (the terminator: leave a skinny triangle whose small angle a small
// input angle causes).
#include "cdt.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/delaunay.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <iterator>
#include <map>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace meshsmith::tessellation {

namespace {

using detail::Cdt;
using detail::Point;
using Vertex = Cdt::Vertex_handle;
using Face = Cdt::Face_handle;

/// Two constrained edges meeting at a vertex at less than 60° form a small input angle.
constexpr double kSmallAngleCosine = 0.5;
/// Below this angle (degrees) a small input angle is narrow. Resolving the inside of a wedge of
/// angle φ into triangles that meet the bound takes of the order of 1/φ Steiner points per
/// doubling of the distance from its apex (the local feature size there is the wedge's width;
/// measured: about 155/φ° points for a sliver of angle φ° and length 1 at 25-30°), which is
/// unbounded as φ → 0 (Triangle and CGAL's mesher run out of points on a 1e-9 rad sliver). The
/// inside of a narrow wedge is therefore left as the ladder of triangles between its two sides
/// (see caused_by_narrow_wedge); wider ones are resolved as Triangle does.
constexpr double kNarrowWedgeDegrees = 0.5;
/// No point is inserted closer than this (2^-40) to the vertices of what it splits (the triangle,
/// or the subsegment's ends): the CDT's coordinates are normalized to magnitudes in [0.5, 1), so
/// points constructed at that scale carry relative errors above 1e-4 (beyond Ruppert's range, at
/// 34°, refinement next to a 1e-15 feature kept inserting such points until the Steiner cap).
const double kInsertionRadius = std::ldexp(1.0, -40);

/// A piece of input segment: a constrained edge of the CDT as built, between two input vertices
/// or crossing points. Steiner points the refinement puts on it remember it (VertexInfo::piece).
struct Piece {
  std::array<Vertex, 2> end;
  std::array<bool, 2> shell_end{{false, false}};  ///< end k is the apex of a small input angle
  std::vector<int> wedges;                        ///< the small input angles it bounds
};

/// A small input angle: two pieces, consecutive around their common end `apex`, meeting at less
/// than 60°.
struct Wedge {
  Vertex apex;
  std::array<int, 2> piece;
  bool narrow;
};

/// A triangle waiting to be split: its vertices (it may be gone when its turn comes) and its
/// priority (area-bad ones first, largest area first; then the smallest angle first).
struct Candidate {
  bool too_big;
  double key;
  std::array<Vertex, 3> v;
  bool operator<(const Candidate& other) const {  // std::priority_queue pops the largest
    if (too_big != other.too_big) return !too_big;
    return too_big ? key < other.key : key > other.key;
  }
};

double squared_length(const Point& a, const Point& b) { return CGAL::squared_distance(a, b); }

class Refiner {
 public:
  Refiner(Cdt& cdt, const RefineOptions& options, double scale, const Progress& progress)
      : cdt_(cdt), progress_(progress), max_steiner_(options.max_steiner_points) {
    const double sine = std::sin(options.min_angle_degrees * M_PI / 180.0);
    squared_sine_bound_ = sine * sine;
    off_centre_factor_ = 0.95 / (2 * std::tan(options.min_angle_degrees * M_PI / 360.0));
    max_area_ = options.max_area * scale * scale;
    narrow_cosine_ = std::cos(kNarrowWedgeDegrees * M_PI / 180.0);
    find_pieces_and_wedges();
  }

  void run() {
    for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f)
      if (f->is_in_domain()) {
        consider_face(f);
        for (int i = 0; i < 3; ++i)
          if (f->is_constrained(i) && encroached_by(f->vertex(i)->point(), f->vertex(i), edge_ends(f, i)))
            encroached_.emplace_back(edge_ends(f, i));
      }
    std::size_t iterations = 0;
    while (true) {
      if (++iterations % 256 == 0) report_progress();
      if (!encroached_.empty()) {
        const auto [x, y] = encroached_.front();
        encroached_.pop_front();
        Face f;
        int i;
        if (!cdt_.is_edge(x, y, f, i) || !f->is_constrained(i) || !still_encroached(f, i)) continue;
        split_subsegment(f, i);
        continue;
      }
      if (bad_.empty()) break;
      const Candidate candidate = bad_.top();
      bad_.pop();
      Face f;
      if (!cdt_.is_face(candidate.v[0], candidate.v[1], candidate.v[2], f) || !f->is_in_domain()) continue;
      split_triangle(f, candidate.too_big);
    }
    progress_.report(1.0, "refine");
  }

 private:
  using EdgeEnds = std::pair<Vertex, Vertex>;

  static EdgeEnds edge_ends(Face f, int i) { return {f->vertex(Cdt::ccw(i)), f->vertex(Cdt::cw(i))}; }

  bool in_domain(Face f) const { return !cdt_.is_infinite(f) && f->is_in_domain(); }

  // --- the input's pieces and small angles ---------------------------------------------------
  static std::pair<const void*, const void*> key(Vertex a, Vertex b) {
    const void* p = &*a;
    const void* q = &*b;
    return p < q ? std::make_pair(p, q) : std::make_pair(q, p);
  }

  void find_pieces_and_wedges() {
    for (auto e = cdt_.finite_edges_begin(); e != cdt_.finite_edges_end(); ++e) {
      if (!cdt_.is_constrained(*e)) continue;
      const auto [a, b] = edge_ends(e->first, e->second);
      piece_of_.emplace(key(a, b), static_cast<int>(pieces_.size()));
      pieces_.push_back(Piece{{a, b}, {{false, false}}, {}});
    }
    struct Direction {
      double angle, x, y;
      int piece;
    };
    std::vector<Direction> directions;
    for (auto v = cdt_.finite_vertices_begin(); v != cdt_.finite_vertices_end(); ++v) {
      directions.clear();
      auto edge = cdt_.incident_edges(v), done = edge;
      if (edge == nullptr) continue;
      do {
        if (cdt_.is_infinite(*edge) || !cdt_.is_constrained(*edge)) continue;
        const auto [a, b] = edge_ends(edge->first, edge->second);
        const Vertex other = a == Vertex(v) ? b : a;
        const double dx = other->point().x() - v->point().x(), dy = other->point().y() - v->point().y();
        const double length = std::hypot(dx, dy);
        directions.push_back({std::atan2(dy, dx), dx / length, dy / length, piece_of_.at(key(a, b))});
      } while (++edge != done);
      if (directions.size() < 2) continue;
      std::sort(directions.begin(), directions.end(),
                [](const Direction& p, const Direction& q) { return p.angle < q.angle; });
      const std::size_t pairs = directions.size() == 2 ? 1 : directions.size();
      for (std::size_t k = 0; k < pairs; ++k) {
        const Direction& d0 = directions[k];
        const Direction& d1 = directions[(k + 1) % directions.size()];
        const double cosine = d0.x * d1.x + d0.y * d1.y;
        if (!(cosine > kSmallAngleCosine)) continue;
        const int w = static_cast<int>(wedges_.size());
        wedges_.push_back(Wedge{v, {d0.piece, d1.piece}, cosine > narrow_cosine_});
        for (const int p : {d0.piece, d1.piece}) {
          pieces_[p].wedges.push_back(w);
          pieces_[p].shell_end[pieces_[p].end[0] == Vertex(v) ? 0 : 1] = true;
          for (const Vertex& end : pieces_[p].end) wedges_at_vertex_[&*end].push_back(w);
        }
      }
    }
    for (auto& [vertex, list] : wedges_at_vertex_) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  }

  /// The piece a constrained edge lies on.
  int piece_of(Vertex a, Vertex b) const {
    if (a->info().piece >= 0) return a->info().piece;
    if (b->info().piece >= 0) return b->info().piece;
    const auto found = piece_of_.find(key(a, b));
    return found == piece_of_.end() ? -1 : found->second;
  }

  bool on_piece(Vertex v, int piece) const {
    return v->info().piece == piece || v == pieces_[piece].end[0] || v == pieces_[piece].end[1];
  }

  bool on_wedge(Vertex v, const Wedge& w) const {
    return v == w.apex || on_piece(v, w.piece[0]) || on_piece(v, w.piece[1]);
  }

  /// The small input angles whose sides hold v (a Steiner point on a side, or a side's end).
  const std::vector<int>& wedges_through(Vertex v) const {
    static const std::vector<int> none;
    if (v->info().piece >= 0) return pieces_[v->info().piece].wedges;
    const auto found = wedges_at_vertex_.find(&*v);
    return found == wedges_at_vertex_.end() ? none : found->second;
  }

  // --- encroachment -------------------------------------------------------------------------
  /// Whether point p (the vertex `by`, or a candidate circumcentre when `by` is null) lies in the
  /// closed diametral circle of the subsegment (x, y). A vertex on one side of a narrow wedge
  /// does not encroach the other side: that is the wedge's own width, which is not resolved.
  bool encroached_by(const Point& p, Vertex by, EdgeEnds ends) const {
    const auto& [x, y] = ends;
    const Point& a = x->point();
    const Point& b = y->point();
    if ((a.x() - p.x()) * (b.x() - p.x()) + (a.y() - p.y()) * (b.y() - p.y()) > 0) return false;
    if (by == Vertex()) return true;
    const int piece = piece_of(x, y);
    if (piece < 0) return true;
    for (const int w : pieces_[piece].wedges) {
      const Wedge& wedge = wedges_[w];
      const int other = wedge.piece[0] == piece ? wedge.piece[1] : wedge.piece[0];
      if (wedge.narrow && (by == wedge.apex || on_piece(by, other))) return false;
    }
    return true;
  }

  /// Whether the constrained edge (f, i) is encroached upon by the apex of a domain face on it.
  bool still_encroached(Face f, int i) const {
    const Face g = f->neighbor(i);
    return (in_domain(f) && encroached_by(f->vertex(i)->point(), f->vertex(i), edge_ends(f, i))) ||
           (in_domain(g) && encroached_by(g->vertex(g->index(f))->point(), g->vertex(g->index(f)), edge_ends(f, i)));
  }

  // --- quality -----------------------------------------------------------------------------
  struct Shape {
    double area, squared_sine;  ///< sin² of the smallest angle
    int shortest;               ///< index of the vertex opposite the shortest edge
  };

  static Shape shape(Face f) {
    const Point& a = f->vertex(0)->point();
    const Point& b = f->vertex(1)->point();
    const Point& c = f->vertex(2)->point();
    const std::array<double, 3> opposite{squared_length(b, c), squared_length(c, a), squared_length(a, b)};
    const int shortest = static_cast<int>(std::min_element(opposite.begin(), opposite.end()) - opposite.begin());
    const double area = CGAL::area(a, b, c);
    // The smallest angle is opposite the shortest edge: sin² = (2·area)² / (product of the two
    // longer squared edge lengths).
    const double longer = opposite[(shortest + 1) % 3] * opposite[(shortest + 2) % 3];
    return {area, longer > 0 ? 4 * area * area / longer : 0.0, shortest};
  }

  void consider_face(Face f) {
    const Shape s = shape(f);
    const bool too_big = max_area_ > 0 && s.area > max_area_;
    if (!too_big && !(s.squared_sine < squared_sine_bound_)) return;
    if (!too_big && seditious(f, s.shortest)) return;
    bad_.push(Candidate{too_big, too_big ? s.area : s.squared_sine, {f->vertex(0), f->vertex(1), f->vertex(2)}});
  }

  /// Triangle's rule (Shewchuk 2002, §6): the shortest edge joins two Steiner points on the two
  /// sides of a small input angle at the same distance from its apex (within 0.1%), points
  /// concentric-shell splitting put there. Splitting the triangle would only make a smaller copy nearer the apex.
  bool seditious(Face f, int shortest) const {
    const Vertex u = f->vertex(Cdt::ccw(shortest)), w = f->vertex(Cdt::cw(shortest));
    if (u->info().piece < 0 || w->info().piece < 0) return false;  // input vertices: not on a shell
    for (const int k : wedges_through(u)) {
      const Wedge& wedge = wedges_[k];
      if (u == wedge.apex || w == wedge.apex) continue;
      const bool spans = (on_piece(u, wedge.piece[0]) && on_piece(w, wedge.piece[1])) ||
                         (on_piece(u, wedge.piece[1]) && on_piece(w, wedge.piece[0]));
      if (!spans) continue;
      const double du = squared_length(u->point(), wedge.apex->point());
      const double dw = squared_length(w->point(), wedge.apex->point());
      if (du < 1.002 * dw && dw < 1.002 * du) return true;  // squared distances: 0.1% on distances
    }
    return false;
  }

  /// The terminator: a skinny triangle inside a narrow wedge (all its vertices on the wedge's
  /// sides or apex) whose split point would have to go onto one of the wedge's sides instead. Its
  /// small angle is the wedge's: it spans the wedge, which is narrower there than it is long.
  bool caused_by_narrow_wedge(Face f, const std::vector<EdgeEnds>& splits) const {
    for (int corner = 0; corner < 3; ++corner)
      for (const int k : wedges_through(f->vertex(corner))) {
        const Wedge& wedge = wedges_[k];
        if (!wedge.narrow || !on_wedge(f->vertex(0), wedge) || !on_wedge(f->vertex(1), wedge) ||
            !on_wedge(f->vertex(2), wedge))
          continue;
        for (const auto& [x, y] : splits) {
          const int piece = piece_of(x, y);
          if (piece == wedge.piece[0] || piece == wedge.piece[1]) return true;
        }
      }
    return false;
  }

  // --- insertion ---------------------------------------------------------------------------
  void count_insertion() {
    if (++inserted_ > static_cast<std::size_t>(max_steiner_))
      throw SolverError("refine: more than max_steiner_points = " + std::to_string(max_steiner_) +
                        " Steiner points needed; raise the limit, lower min_angle or raise max_area");
  }

  /// After inserting v: queue the subsegments its new triangles encroach and the new bad triangles.
  void after_insertion(Vertex v) {
    auto face = cdt_.incident_faces(v), done = face;
    do {
      if (!in_domain(face)) continue;
      consider_face(face);
      for (int i = 0; i < 3; ++i)
        if (face->is_constrained(i) && encroached_by(face->vertex(i)->point(), face->vertex(i), edge_ends(face, i)))
          encroached_.emplace_back(edge_ends(face, i));
    } while (++face != done);
  }

  /// Where subsegment (x, y) of piece p is split: at its midpoint, or, when exactly one end is the
  /// apex of a small input angle, at the power-of-two distance from that apex in (1/3, 2/3] of its
  /// length (concentric shells, Shewchuk 2002 §6; the CDT's coordinates are normalized by a power
  /// of two, so the shells are scale-invariant).
  Point split_point(Vertex x, Vertex y) const {
    const int piece = piece_of(x, y);
    const auto at_apex = [&](Vertex v) {
      if (piece < 0) return false;
      const Piece& p = pieces_[piece];
      return (v == p.end[0] && p.shell_end[0]) || (v == p.end[1] && p.shell_end[1]);
    };
    const bool from_x = at_apex(x), from_y = at_apex(y);
    const Point& a = x->point();
    const Point& b = y->point();
    if (from_x == from_y) return Point((a.x() + b.x()) / 2, (a.y() + b.y()) / 2);
    const Point& apex = from_x ? a : b;
    const Point& other = from_x ? b : a;
    const double length = std::sqrt(squared_length(a, b));
    int exponent = 0;
    std::frexp(2 * length / 3, &exponent);  // 2^(exponent-1) <= 2/3 length < 2^exponent
    const double t = std::ldexp(1.0, exponent - 1) / length;
    return Point(apex.x() + t * (other.x() - apex.x()), apex.y() + t * (other.y() - apex.y()));
  }

  /// Splits the constrained edge (f, i). Returns false when it is shorter than 2 kInsertionRadius
  /// or its rounded split point would not lie strictly inside the two triangles on it.
  bool split_subsegment(Face f, int i) {
    const auto [x, y] = edge_ends(f, i);
    if (squared_length(x->point(), y->point()) < 4 * kInsertionRadius * kInsertionRadius) return false;
    const Point m = split_point(x, y);
    const Face g = f->neighbor(i);
    for (const Face h : {f, g}) {
      if (cdt_.is_infinite(h)) continue;
      const int apex_index = h == f ? i : g->index(f);
      const Point& a = h->vertex(Cdt::ccw(apex_index))->point();
      const Point& b = h->vertex(Cdt::cw(apex_index))->point();
      const Point& c = h->vertex(apex_index)->point();
      if (CGAL::orientation(a, m, c) != CGAL::LEFT_TURN || CGAL::orientation(m, b, c) != CGAL::LEFT_TURN) return false;
    }
    const int piece = piece_of(x, y);
    const bool left = in_domain(f), right = in_domain(g);
    count_insertion();
    const Vertex v = cdt_.insert(m, Cdt::EDGE, f, i);
    v->info().piece = piece;
    // The faces around v: those left of x → v → y (f's side) until the edge v-x, then g's side.
    auto face = cdt_.incident_faces(v), done = face;
    while (face->vertex(Cdt::ccw(face->index(v))) != y) ++face;  // the face left of v → y
    done = face;
    bool side = left;
    do {
      face->set_in_domain(!cdt_.is_infinite(face) && side);
      if (face->vertex(Cdt::cw(face->index(v))) == x) side = right;
    } while (++face != done);
    after_insertion(v);
    return true;
  }

  /// Straight walk from the centroid of f towards p. Returns the face holding p and -1, or the
  /// face and index of the first constrained edge in the way; a null face if the walk fails.
  std::pair<Face, int> walk(Face f, const Point& p) const {
    const Point& a = f->vertex(0)->point();
    const Point& b = f->vertex(1)->point();
    const Point& c = f->vertex(2)->point();
    const Point from((a.x() + b.x() + c.x()) / 3, (a.y() + b.y() + c.y()) / 3);
    if (CGAL::orientation(a, b, from) != CGAL::LEFT_TURN || CGAL::orientation(b, c, from) != CGAL::LEFT_TURN ||
        CGAL::orientation(c, a, from) != CGAL::LEFT_TURN)
      return {Face(), -1};  // thinner than double precision can tell
    Face previous;
    // The TDS's face count is O(1) (Triangulation_2::number_of_faces() circulates around the
    // infinite vertex: half the refinement's time when it was the loop's bound).
    const std::size_t faces = cdt_.tds().number_of_faces();
    for (std::size_t step = 0; step <= faces; ++step) {
      int exit = -1;
      for (int i = 0; i < 3 && exit < 0; ++i) {
        if (f->neighbor(i) == previous) continue;
        const Point& u = f->vertex(Cdt::ccw(i))->point();
        const Point& w = f->vertex(Cdt::cw(i))->point();
        if (CGAL::orientation(u, w, p) != CGAL::RIGHT_TURN) continue;  // p is not beyond this edge
        const CGAL::Orientation ou = CGAL::orientation(from, p, u), ow = CGAL::orientation(from, p, w);
        if (ou != ow || ou == CGAL::COLLINEAR) exit = i;
      }
      if (exit < 0) return {f, -1};
      if (f->is_constrained(exit)) return {f, exit};
      previous = f;
      f = f->neighbor(exit);
      if (cdt_.is_infinite(f)) return {Face(), -1};
    }
    return {Face(), -1};
  }

  /// The point that splits the bad triangle f: its circumcentre, or its off-centre when that is
  /// nearer the shortest edge pq (Üngör 2004, "Off-centers: a new type of Steiner points for
  /// computing size-optimal quality-guaranteed Delaunay triangulations"): the point on the
  /// bisector of pq, towards the circumcentre, that makes with p and q a triangle whose angle
  /// there is a little above the bound (its distance from pq's midpoint is 0.95 |pq| / (2
  /// tan(min_angle / 2))), so fewer points are needed than with circumcentres alone (measured:
  /// 30-60% fewer at 25-30°; 0.5 or 1.2 times that distance gave more points on every test domain).
  Point steiner_point(Face f) const {
    const Point& a = f->vertex(0)->point();
    const Point& b = f->vertex(1)->point();
    const Point& c = f->vertex(2)->point();
    const Point centre = CGAL::circumcenter(a, b, c);
    const int shortest = shape(f).shortest;
    const Point& p = f->vertex(Cdt::ccw(shortest))->point();
    const Point& q = f->vertex(Cdt::cw(shortest))->point();
    const double mx = (p.x() + q.x()) / 2, my = (p.y() + q.y()) / 2;
    const double dx = centre.x() - mx, dy = centre.y() - my;
    const double reach = off_centre_factor_ * std::sqrt(squared_length(p, q));
    const double distance = std::hypot(dx, dy);
    // An off-centre closer than kInsertionRadius to p and q would be dropped; the circumcentre,
    // farther away, may still be accurate enough.
    if (!(distance > reach) || reach < kInsertionRadius) return centre;
    return Point(mx + dx * (reach / distance), my + dy * (reach / distance));
  }

  /// Ruppert's step for the bad triangle f: insert its circumcentre (or off-centre), unless that point encroaches
  /// subsegments (or lies beyond one): then split those instead and try f again later, or, by the
  /// terminator, leave f alone.
  void split_triangle(Face f, bool too_big) {
    const Point c = steiner_point(f);
    for (int k = 0; k < 3; ++k)  // too small for double precision: left alone
      if (squared_length(c, f->vertex(k)->point()) < kInsertionRadius * kInsertionRadius) return;
    const auto [located, blocking] = walk(f, c);
    if (located == Face()) return;  // too thin for double precision: left alone
    std::vector<EdgeEnds> splits;
    if (blocking >= 0) {
      splits.push_back(edge_ends(located, blocking));
    } else {
      conflicts_.clear();
      boundary_.clear();
      cdt_.get_conflicts_and_boundary(c, std::back_inserter(conflicts_), std::back_inserter(boundary_), located);
      if (conflicts_.empty()) return;  // c is an existing vertex (rounding): left alone
      for (const auto& [g, j] : boundary_)
        if (g->is_constrained(j) && encroached_by(c, Vertex(), edge_ends(g, j))) splits.push_back(edge_ends(g, j));
    }
    if (splits.empty()) {
      count_insertion();
      const Vertex v = cdt_.insert(c, located);
      auto face = cdt_.incident_faces(v), done = face;
      do face->set_in_domain(true);
      while (++face != done);
      after_insertion(v);
      return;
    }
    if (!too_big && caused_by_narrow_wedge(f, splits)) return;
    const std::array<Vertex, 3> corners{f->vertex(0), f->vertex(1), f->vertex(2)};
    bool split_any = false;
    for (const auto& [x, y] : splits) {
      Face g;
      int j;
      if (cdt_.is_edge(x, y, g, j) && g->is_constrained(j)) split_any = split_subsegment(g, j) || split_any;
    }
    Face again;
    if (split_any && cdt_.is_face(corners[0], corners[1], corners[2], again) && again->is_in_domain())
      consider_face(again);
  }

  void report_progress() {
    const double queued = static_cast<double>(bad_.size() + encroached_.size());
    fraction_ = std::max(fraction_, std::min(0.99, inserted_ / (inserted_ + queued + 1.0)));
    progress_.report(fraction_, "refine");
  }

  Cdt& cdt_;
  const Progress& progress_;
  int max_steiner_;
  double squared_sine_bound_ = 0, off_centre_factor_ = 1, max_area_ = 0, narrow_cosine_ = 1;
  std::vector<Piece> pieces_;
  std::map<std::pair<const void*, const void*>, int> piece_of_;
  std::vector<Wedge> wedges_;
  std::map<const void*, std::vector<int>> wedges_at_vertex_;
  std::priority_queue<Candidate> bad_;
  std::deque<EdgeEnds> encroached_;
  std::vector<Face> conflicts_;
  std::vector<Cdt::Edge> boundary_;
  std::size_t inserted_ = 0;
  double fraction_ = 0;
};

}  // namespace

PlanarMesh refine(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes,
                  const RefineOptions& options, const Progress& progress) {
  if (!(options.min_angle_degrees > 0 && options.min_angle_degrees < 35))
    throw InputError("min_angle: must be in (0, 35) degrees, got " + std::to_string(options.min_angle_degrees));
  if (!(options.max_area >= 0) || !std::isfinite(options.max_area))
    throw InputError("max_area: must be a finite number >= 0, got " + std::to_string(options.max_area));
  if (options.max_steiner_points < 0) throw InputError("max_steiner_points: must be >= 0");
  Cdt cdt;
  const double scale = detail::build_domain(P, segments, holes, cdt);
  progress.report(0.0, "refine");
  Refiner(cdt, options, scale, progress).run();
  return detail::extract_domain(P, cdt, scale);
}

}  // namespace meshsmith::tessellation
