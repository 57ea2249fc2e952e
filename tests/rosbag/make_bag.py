"""Writes ROS 2 bags (MCAP storage) for lplace's rosbag2 tests, with the `rosbags` library.

    python make_bag.py intel CARMEN_LOG OUT_DIR   # the CARMEN log as /scan, /odom and /truth
    python make_bag.py errors OUT_DIR             # small bags with broken messages

The CARMEN log becomes what a ROS 2 robot would have recorded:
- /scan, sensor_msgs/msg/LaserScan, one per FLASER line: stamp = ipc_ts, frame_id "laser",
  angle_min -pi/2, angle_increment pi/n (pi/(n-1) for odd n: the FLASER convention),
  range_min 0, range_max 81.91 (the SICK LMS limit, above every range in the log).
- /odom, nav_msgs/msg/Odometry, frame "odom", child "base_link": the raw odometry as one
  continuous track. In the corrected logs the ODOM lines are re-chained from the last scan's
  corrected pose, so each segment is moved back onto the track: after scan k, an ODOM pose q
  becomes O_k (+) (P_k (-) q), with P_k the scan's pose slot and O_k the track at scan k. A scan
  with no ODOM line since the previous one gets an Odometry at its own stamp (O_k (+) (P_k (-)
  P_k+1)), which is what the CARMEN reader falls back to as well.
- /truth, geometry_msgs/msg/PoseStamped in "map": the scan's (corrected) pose, one per scan,
  written just before it.
Messages are written in log order, log time = header stamp.
"""

import math
import sys
from pathlib import Path

from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

TS = get_typestore(Stores.ROS2_HUMBLE)
T = TS.types
Time = T['builtin_interfaces/msg/Time']
Header = T['std_msgs/msg/Header']
Point = T['geometry_msgs/msg/Point']
Quaternion = T['geometry_msgs/msg/Quaternion']
Pose = T['geometry_msgs/msg/Pose']
PoseStamped = T['geometry_msgs/msg/PoseStamped']
PoseCov = T['geometry_msgs/msg/PoseWithCovariance']
Twist = T['geometry_msgs/msg/Twist']
TwistCov = T['geometry_msgs/msg/TwistWithCovariance']
Vector3 = T['geometry_msgs/msg/Vector3']
LaserScan = T['sensor_msgs/msg/LaserScan']
Odometry = T['nav_msgs/msg/Odometry']

try:
    import numpy as np
except ImportError:  # rosbags depends on numpy; this is only for a clear message
    sys.exit('numpy is required (a dependency of rosbags)')


def stamp(t):
    """A ROS time for t seconds, rounded to the nanosecond."""
    ns = round(t * 1e9)
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000), ns


def header(t, frame):
    st, ns = stamp(t)
    return Header(stamp=st, frame_id=frame), ns


def pose(x, y, theta):
    return Pose(
        position=Point(x=x, y=y, z=0.0),
        orientation=Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2)),
    )


def odometry(t, x, y, theta):
    h, ns = header(t, 'odom')
    zero = Vector3(x=0.0, y=0.0, z=0.0)
    msg = Odometry(
        header=h,
        child_frame_id='base_link',
        pose=PoseCov(pose=pose(x, y, theta), covariance=np.zeros(36)),
        twist=TwistCov(twist=Twist(linear=zero, angular=zero), covariance=np.zeros(36)),
    )
    return msg, ns


def scan(t, ranges):
    n = len(ranges)
    step = math.pi if n < 2 else math.pi / (n if n % 2 == 0 else n - 1)
    h, ns = header(t, 'laser')
    msg = LaserScan(
        header=h,
        angle_min=-math.pi / 2,
        angle_max=-math.pi / 2 + step * (n - 1),
        angle_increment=step,
        time_increment=0.0,
        scan_time=0.0,
        range_min=0.0,
        range_max=81.91,
        ranges=np.array(ranges, dtype=np.float32),
        intensities=np.zeros(0, dtype=np.float32),
    )
    return msg, ns


def relative(a, b):
    """a (-) b: b in the frame of a."""
    s, c = math.sin(a[2]), math.cos(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, b[2] - a[2])


def compose(a, d):
    """a (+) d."""
    s, c = math.sin(a[2]), math.cos(a[2])
    return (a[0] + c * d[0] - s * d[1], a[1] + s * d[0] + c * d[1], a[2] + d[2])


def read_carmen(path):
    """Yields ('laser', t, ranges, pose, odom_pose) and ('odom', t, pose) in log order."""
    with open(path, encoding='utf-8') as f:
        for line in f:
            w = line.split()
            if not w or w[0].startswith('#'):
                continue
            if w[0] == 'FLASER':
                n = int(w[1])
                r = [float(x) for x in w[2:2 + n]]
                v = [float(x) for x in w[2 + n:2 + n + 7]]
                yield 'laser', v[6], r, tuple(v[0:3]), tuple(v[3:6])
            elif w[0] == 'ODOM':
                v = [float(x) for x in w[1:8]]
                yield 'odom', v[6], tuple(v[0:3])


def write_intel(log, out):
    with Writer(out, version=9, storage_plugin=StoragePlugin.MCAP) as bag:
        c_scan = bag.add_connection('/scan', LaserScan.__msgtype__, typestore=TS)
        c_odom = bag.add_connection('/odom', Odometry.__msgtype__, typestore=TS)
        c_truth = bag.add_connection('/truth', PoseStamped.__msgtype__, typestore=TS)

        def put(conn, msg, ns):
            bag.write(conn, ns, TS.serialize_cdr(msg, type(msg).__msgtype__))

        track = None  # O_k: the continuous odometry at the last scan
        anchor = None  # P_k: the last scan's odom pose slot (the corrected pose)
        last = None  # the last track pose written
        pending = None  # the last ODOM pose since the last scan, on the track
        scans = 0
        for rec in read_carmen(log):
            if rec[0] == 'odom':
                _, t, q = rec
                if anchor is None:
                    continue  # before the first scan: nothing to chain to (the reader skips these too)
                pending = compose(track, relative(anchor, q))
                put(c_odom, *odometry(t, *pending))
                last = pending
                continue
            _, t, ranges, p, odom_p = rec
            if track is None:
                track = odom_p  # the track starts where the log does
                put(c_odom, *odometry(t, *track))
            elif pending is None:
                track = compose(track, relative(anchor, odom_p))
                put(c_odom, *odometry(t, *track))
            else:
                track = pending
            anchor, pending, last = odom_p, None, track
            h, ns = header(t, 'map')
            put(c_truth, PoseStamped(header=h, pose=pose(*p)), ns)
            put(c_scan, *scan(t, ranges))
            scans += 1
    print(f'make_bag: {scans} scans written to {out}')


def write_errors(out):
    """One bag per broken case, each with good messages around the broken one."""
    cases = {
        'truncated_scan': 'a LaserScan payload cut in the middle of its ranges',
        'wrong_type': 'a message of another type on the scan topic',
    }
    out.mkdir(parents=True, exist_ok=True)
    for name in cases:
        with Writer(out / name, version=9, storage_plugin=StoragePlugin.MCAP) as bag:
            c_scan = bag.add_connection('/scan', LaserScan.__msgtype__, typestore=TS)
            c_odom = bag.add_connection('/odom', Odometry.__msgtype__, typestore=TS)
            if name == 'wrong_type':
                c_bad = bag.add_connection('/scan', PoseStamped.__msgtype__, typestore=TS)
            for k in range(5):
                t = 1.0 + 0.2 * k
                o, ns = odometry(t, 0.1 * k, 0.0, 0.0)
                bag.write(c_odom, ns, TS.serialize_cdr(o, Odometry.__msgtype__))
                s, ns = scan(t, [1.0 + 0.01 * i for i in range(180)])
                data = TS.serialize_cdr(s, LaserScan.__msgtype__)
                if k == 2 and name == 'truncated_scan':
                    data = data[: len(data) // 2]
                if k == 2 and name == 'wrong_type':
                    h, ns = header(t, 'map')
                    data = TS.serialize_cdr(PoseStamped(header=h, pose=pose(0, 0, 0)), PoseStamped.__msgtype__)
                    bag.write(c_bad, ns, data)
                    continue
                bag.write(c_scan, ns, data)
    print(f'make_bag: error bags {", ".join(cases)} written to {out}')


def main(argv):
    if len(argv) == 4 and argv[1] == 'intel':
        write_intel(Path(argv[2]), Path(argv[3]))
    elif len(argv) == 3 and argv[1] == 'errors':
        write_errors(Path(argv[2]))
    else:
        sys.exit(__doc__)


if __name__ == '__main__':
    main(sys.argv)
