#include "model/link_frames.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "fluid/box_union.h"
#include "model/model_error.h"

namespace flapsim {

namespace {

using Mat3 = Eigen::Matrix3d;

std::string moments(const Vec3& p) {
  std::ostringstream out;
  out.precision(6);
  out << "principal moments " << p.x() << ", " << p.y() << ", " << p.z() << " kg m^2";
  return out.str();
}

// Refuses principal moments `p` that are not all positive or break the triangle inequality
// (each at most the sum of the other two, up to 1 % of their sum: a thin plate's are equal,
// and files round them, e.g. 3.33e-06, 3.33e-06, 6.67e-06, which breaks it by 0.08 %).
void checkMoments(const Vec3& p, const std::string& where, const std::string& source) {
  if (!p.allFinite()) fail(source, where + ": inertia must be finite");
  if (!(p.minCoeff() > 0.0)) {
    fail(source, where + ": inertia tensor is not positive definite (" + moments(p) + ")");
  }
  const double sum = p.sum();
  for (int i = 0; i < 3; ++i) {
    if (p[i] > sum - p[i] + 1e-2 * sum) {
      fail(source, where + ": inertia violates the triangle inequality (" + moments(p) +
                       ": each must be at most the sum of the other two)");
    }
  }
}

// The principal axes of `inertia` as the columns of a proper rotation, their moments in
// `p`: eigenvector i goes to the axis it is nearest to (the permutation with the largest
// sum of |R(i, i)|, the first such in lexicographic order), pointing along it.
Mat3 principalAxes(const Mat3& inertia, Vec3& p) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(inertia);
  const Mat3 v = solver.eigenvectors();
  int perm[3] = {0, 1, 2}, best[3] = {0, 1, 2};
  double best_sum = -1.0;
  do {
    const double sum = std::abs(v(0, perm[0])) + std::abs(v(1, perm[1])) + std::abs(v(2, perm[2]));
    if (sum > best_sum) {
      best_sum = sum;
      std::copy(perm, perm + 3, best);
    }
  } while (std::next_permutation(perm, perm + 3));
  Mat3 r;
  for (int i = 0; i < 2; ++i) {
    r.col(i) = v.col(best[i]) * (v(i, best[i]) < 0.0 ? -1.0 : 1.0);
  }
  r.col(2) = r.col(0).cross(r.col(1));
  p = Vec3(solver.eigenvalues()[best[0]], solver.eigenvalues()[best[1]],
           solver.eigenvalues()[best[2]]);
  return r;
}

}  // namespace

void setInertia(LinkModel& link, const Quat& inertial_rotation, const double (&t)[6],
                const std::string& source) {
  const std::string where = "link '" + link.name + "'";
  for (double v : t) {
    if (!std::isfinite(v)) fail(source, where + ": inertia must be finite");
  }
  const bool turned = !inertial_rotation.isApprox(Quat::Identity(), 1e-12) &&
                      !inertial_rotation.isApprox(Quat(-1, 0, 0, 0), 1e-12);
  if (!turned && t[1] == 0.0 && t[2] == 0.0 && t[4] == 0.0) {
    // Diagonal in the URDF frame: its axes are the principal ones, as before (bit for bit).
    link.inertia = Vec3(t[0], t[3], t[5]);
    link.urdf_frame = Pose();
    checkMoments(link.inertia, where, source);
    return;
  }
  Mat3 given;
  given << t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5];
  const Mat3 q = turned ? inertial_rotation.normalized().toRotationMatrix() : Mat3::Identity();
  const Mat3 inertia = q * given * q.transpose();  // about the COM, URDF link axes
  Vec3 p;
  const Mat3 r = principalAxes(inertia, p);
  checkMoments(p, where, source);
  link.inertia = p;
  link.urdf_frame = Pose{Vec3::Zero(), Quat(r).conjugate().normalized()};
  if (!link.rotated()) link.urdf_frame = Pose();
}

namespace {

bool massless(const CreatureModel& m, int k) {
  return m.links[k].mass == 0.0 && !(k == 0 && m.fixed_base);
}

// Makes the first link with mass that fixed joints join to the massless root (through
// massless links only) the root: the joints on the way are reversed. Returns the way, from
// the new root to the old one.
std::vector<int> reroot(CreatureModel& m, const std::string& source) {
  std::vector<int> via(m.links.size(), -1), todo{0};
  int root = -1;
  for (size_t i = 0; i < todo.size() && root < 0; ++i) {
    for (size_t j = 0; j < m.joints.size() && root < 0; ++j) {
      const JointModel& joint = m.joints[j];
      if (joint.parent_link != todo[i] || joint.movable()) continue;
      via[joint.child_link] = static_cast<int>(j);
      if (massless(m, joint.child_link)) {
        todo.push_back(joint.child_link);
      } else {
        root = joint.child_link;
      }
    }
  }
  if (root < 0) {
    fail(source, "link '" + m.links[0].name +
                     "' has no positive mass (<inertial><mass value=.../>) and no link with mass"
                     " is fixed to it");
  }
  m.links[root].parent_joint = -1;
  std::vector<int> way{root};
  for (int c = root; c != 0;) {
    const int j = via[c];
    JointModel& joint = m.joints[j];
    std::swap(joint.parent_link, joint.child_link);
    joint.origin = joint.origin.inverse();
    m.links[joint.child_link].parent_joint = j;
    c = joint.child_link;
    way.push_back(c);
  }
  return way;
}

// Moves the shapes of massless link `k` to link `host`, `pose` being k's frame in host's.
void moveShapes(LinkModel& k, LinkModel& host, const Pose& pose, const std::string& source) {
  if (!k.hasShapes()) return;
  const std::string where = "link '" + k.name + "'";
  if (host.mass == 0.0) fail(source, where + " has shapes but no mass: it is fixed to the world");
  for (Box b : k.boxes) {
    b.origin = pose * b.origin;
    host.boxes.push_back(b);
  }
  for (RoundShape r : k.rounds) {
    r.origin = pose * r.origin;
    host.rounds.push_back(r);
  }
  for (MeshShape mesh : k.meshes) {
    mesh.origin = pose * mesh.origin;
    host.meshes.push_back(mesh);
  }
  host.shapes_from_visuals = host.shapes_from_visuals || k.shapes_from_visuals;
  const size_t shapes = host.boxes.size() + host.rounds.size() + host.meshes.size();
  if (shapes > static_cast<size_t>(kMaxShapesPerLink) ||
      turnedOverlaps(host.boxes) > static_cast<size_t>(kMaxTurnedOverlaps)) {
    fail(source, "link '" + host.name + "' with " + where +
                     " lumped into it (no mass, fixed joint): over the limit of shapes (" +
                     std::to_string(kMaxShapesPerLink) + ") or turned overlaps (" +
                     std::to_string(kMaxTurnedOverlaps) + ") per link");
  }
}

// The model without the lumped links: links `order` (root first) less the massless ones.
void keepLinks(CreatureModel& m, const std::vector<int>& order) {
  std::vector<int> link_index(m.links.size(), -1), joint_index(m.joints.size(), -1);
  std::vector<LinkModel> links;
  for (int k : order) {
    if (massless(m, k)) continue;
    link_index[k] = static_cast<int>(links.size());
    links.push_back(std::move(m.links[k]));
  }
  std::vector<JointModel> joints;
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (link_index[m.joints[j].child_link] < 0) continue;
    joint_index[j] = static_cast<int>(joints.size());
    joints.push_back(m.joints[j]);
  }
  for (JointModel& j : joints) {
    j.parent_link = link_index[j.parent_link];
    j.child_link = link_index[j.child_link];
    if (j.feather_joint >= 0) j.feather_joint = joint_index[j.feather_joint];
  }
  for (LinkModel& l : links) {
    if (l.parent_joint >= 0) l.parent_joint = joint_index[l.parent_joint];
  }
  for (int& w : m.wing_joints) w = joint_index[w];
  for (LumpedLink& l : m.lumped) l.link = link_index[l.link];
  m.links = std::move(links);
  m.joints = std::move(joints);
}

}  // namespace

void lumpMasslessLinks(CreatureModel& m, const std::set<std::string>& aero_links,
                       const std::string& source) {
  const int n = static_cast<int>(m.links.size());
  bool any = false;
  for (int k = 0; k < n; ++k) any = any || massless(m, k);
  if (!any) return;
  for (const JointModel& j : m.joints) {
    if (j.movable() && massless(m, j.child_link)) {
      fail(source, "link '" + m.links[j.child_link].name + "' has no positive mass and moves on " +
                       "joint '" + j.name + "': only a link on a fixed joint may have none (it" +
                       " is lumped into its parent)");
    }
  }
  // Parent before child: the way from a new root to the old one, then the URDF's order.
  std::vector<int> order = massless(m, 0) ? reroot(m, source) : std::vector<int>{0};
  const int root = order[0];
  for (int k = 0; k < n; ++k) {
    if (std::find(order.begin(), order.end(), k) == order.end()) order.push_back(k);
  }
  std::vector<int> host(n);
  std::vector<Pose> pose(n);  // link k's URDF frame in its host's
  for (const int k : order) {
    host[k] = k;
    if (k == root) continue;
    JointModel& j = m.joints[m.links[k].parent_joint];
    const int p = j.parent_link;
    if (massless(m, k)) {
      host[k] = host[p];
      pose[k] = pose[p] * j.origin;
      if (aero_links.count(m.links[k].name)) {
        fail(source, "<aero link='" + m.links[k].name + "'>: the link has no mass and is lumped" +
                         " into '" + m.links[host[k]].name + "': give its <aero> to that link");
      }
      moveShapes(m.links[k], m.links[host[k]], pose[k], source);
      // The URDF root (link 0) hangs on a reversed joint now; it hung on none.
      m.lumped.push_back(
          LumpedLink{m.links[k].name, k == 0 ? std::string() : j.name, host[k], pose[k]});
    } else if (host[p] != p) {
      j.origin = pose[p] * j.origin;
      j.parent_link = host[p];
    }
  }
  keepLinks(m, order);
}

void expressInLinkFrames(CreatureModel& m) {
  for (size_t k = 0; k < m.links.size(); ++k) {
    LinkModel& l = m.links[k];
    if (!l.rotated()) continue;
    const Pose f = l.urdf_frame;  // the URDF frame in the link frame
    l.com = f.orientation * l.com;
    for (Box& b : l.boxes) b.origin = f * b.origin;
    for (RoundShape& r : l.rounds) r.origin = f * r.origin;
    for (MeshShape& mesh : l.meshes) mesh.origin = f * mesh.origin;
    if (l.aero.span) l.aero.span = Vec3(f.orientation * *l.aero.span);
    for (JointModel& j : m.joints) {
      if (j.parent_link == static_cast<int>(k)) j.origin = f * j.origin;
      if (j.child_link == static_cast<int>(k)) {
        j.origin = j.origin * f.inverse();
        j.axis = f.orientation * j.axis;
      }
    }
  }
}

}  // namespace flapsim
