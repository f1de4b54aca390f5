"""The camera the Python rostests publish their drawn frames from (imported from the test's own
directory): a 640 x 480 pinhole without distortion, focal length FOCAL px, centred."""
from sensor_msgs.msg import CameraInfo

FOCAL = 500.0  # px
WIDTH, HEIGHT = 640, 480


def camera_info(frame_id):
    """The camera's CameraInfo in `frame_id`."""
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width, info.height = WIDTH, HEIGHT
    cx, cy = (WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0
    info.distortion_model = "plumb_bob"
    info.D = [0.0] * 5
    info.K = [FOCAL, 0, cx, 0, FOCAL, cy, 0, 0, 1]
    info.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    info.P = [FOCAL, 0, cx, 0, 0, FOCAL, cy, 0, 0, 0, 1, 0]
    return info
