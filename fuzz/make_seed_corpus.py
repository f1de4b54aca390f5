#!/usr/bin/python3
"""Writes the seed corpus of the fuzz targets into fuzz/corpus/<target>/ (a few KB in all).

usage: fuzz/make_seed_corpus.py      (Debian's python3 with python3-opencv and python3-numpy)

The seeds are small valid inputs of each target's format (see the comment at the top of each
fuzz_<target>.cpp); the fuzzer mutates them. Run it again after changing a format.
"""

import os
import struct
import tempfile

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def silhouette(size=24, shape="disc"):
    image = np.full((size, size), 255, np.uint8)
    if shape == "disc":
        cv2.circle(image, (size // 2, size // 2), size // 3, 0, -1)
    else:
        cv2.fillPoly(image, [np.array([[4, size - 4], [size // 2, 3], [size - 4, size - 6]], np.int32)], 0)
    return image


def encoded(ext, image, params=()):
    ok, data = cv2.imencode(ext, image, list(params))
    assert ok, ext
    return data.tobytes()


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as out:
        out.write(data)


def tiny_video():
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "seed.avi")
        writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*"MJPG"), 10, (16, 16), False)
        for shift in range(2):
            frame = np.full((16, 16), 255, np.uint8)
            cv2.circle(frame, (5 + 2 * shift, 8), 4, 0, -1)
            writer.write(frame)
        writer.release()
        with open(path, "rb") as video:
            return video.read()


def main():
    disc, triangle = silhouette(), silhouette(shape="triangle")
    colour = cv2.cvtColor(triangle, cv2.COLOR_GRAY2BGR)
    colour[:, :, 2] = 200

    write("prototype_loader", "disc.png", encoded(".png", disc))
    write("prototype_loader", "triangle.jpg", encoded(".jpg", triangle, [cv2.IMWRITE_JPEG_QUALITY, 60]))
    write("prototype_loader", "colour16.png", encoded(".png", colour.astype(np.uint16) * 257))
    write("prototype_loader", "triangle.pgm", encoded(".pgm", silhouette(12, "triangle")))

    write("param_file", "counts.yaml", b"%YAML:1.0\n---\nnum_v_particles: 60\nm_particles_per_prototype: 60\n"
          b"seed: 42\nprototype_size: 128\n")
    write("param_file", "forms.yaml", b"%YAML:1.0\n---\nlikelihood_form: \"mixture\"\ndeviation_space: \"prototype\"\n"
          b"sigma_w: 5.0\np_outlier: 0.1\nmax_ray_length: 200.0\n")
    write("param_file", "priors.yaml", b"%YAML:1.0\n---\nprototype_priors:\n  disc: 2.0\n  triangle: 0.5\n"
          b"min_support: 3\n")
    write("param_file", "priors_text.yaml", b"%YAML:1.0\n---\nprototype_priors: \"a: 1, b: 0.25\"\n")
    # Inputs on which OpenCV's YAML reader (before yaml-cpp) never returned (test_fuzz_regressions.cpp),
    # and YAML forms a parameter file may now hold (an anchor and an alias, a flow map of priors).
    write("param_file", "hang_document_marker.yaml", b"%YAML:1.\n---s:0\n\")--\nr")
    write("param_file", "hang_tagged_key.yaml", b"%YAML:1.0\n---\n!p:\n  d: 2.0\nmyn-\nl: 3\n")
    write("param_file", "hang_indented_end.yaml", b" sigma_w: 2.0\n ...--\n  p_invalid: 0.5\n")
    write("param_file", "anchor_flow.yaml", b"sigma_w: &w 6\nverify_tolerance: *w\nprototype_priors: {a: 1, b: 0x10}\n"
          b"optical_flow: false\n")

    # image_message: encoding index, width, height, step (u32 LE), is_bigendian, data.
    def message(index, width, height, step, big_endian, data):
        return struct.pack("<BIIIB", index, width, height, step, big_endian) + data

    grey = silhouette(8)
    write("image_message", "mono8", message(0, 8, 8, 8, 0, grey.tobytes()))
    write("image_message", "mono16_be", message(1, 4, 4, 8, 1, (grey[:4, :4].astype(">u2") * 257).tobytes()))
    write("image_message", "bgr8_padded", message(2, 4, 3, 16, 0, bytes(range(48))))
    write("image_message", "bayer", message(10, 4, 4, 4, 0, grey[:4, :4].tobytes()))
    write("image_message", "yuv422", message(18, 4, 2, 8, 0, bytes(range(16))))
    write("image_message", "named_32FC1", struct.pack("<BB", 255, 5) + b"32FC1" +
          struct.pack("<IIIB", 2, 2, 8, 0) + np.full(4, 0.5, np.float32).tobytes())

    # frame_source: byte 0 picks the extension (fuzz_frame_source.cpp, kExtensions), the rest is the file.
    write("frame_source", "png", bytes([0]) + encoded(".png", disc))
    write("frame_source", "jpg", bytes([1]) + encoded(".jpg", triangle, [cv2.IMWRITE_JPEG_QUALITY, 60]))
    write("frame_source", "avi", bytes([9]) + tiny_video())


if __name__ == "__main__":
    main()
