// Reading one image file with the checks a decoder does not make: libjpeg
// decodes a truncated JPEG with a grey lower part and only prints a line,
// so a damaged file would be used as if it were whole.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace amcr
{
/// Reads the image file at `path` (cv::imdecode with `flags`). Before
/// decoding, what can be checked from the bytes is checked:
///  - the file: it exists, is a regular file, can be read (the reason from
///    the system otherwise: permission denied, a directory, no such file),
///    and holds at most kMaxImageFileBytes;
///  - a JPEG: it starts with SOI, its marker segments walk consistently
///    (each starts with 0xFF and fits in the file) up to the first SOS,
///    and an EOI follows the scan data (bytes after the EOI are allowed);
///  - a PNG: its chunks walk consistently from the signature to IEND;
///  - the size in the JPEG's SOF or the PNG's IHDR (or, for other formats,
///    of the decoded image) is at most kMaxImagePixels.
/// Not detectable this way: damage inside a JPEG's entropy-coded data that
/// keeps the markers intact (it decodes to a wrong picture), a JPEG cut
/// within its data and closed again with an EOI, and damage to formats
/// other than JPEG and PNG that their decoders accept (BMP, PNM, TIFF, ...).
/// A PNG's chunk checksums are checked by libpng when it decodes.
/// Throws InputError naming the file and the damage, e.g.
/// "truncated JPEG 'a.jpg': no end-of-image marker after the scan data".
cv::Mat readImageFile(const std::string& path, int flags = cv::IMREAD_UNCHANGED);

/// readImageFile() in two steps, for a caller that needs the file's bytes
/// (the table cache names an image by them): the file checks and its
/// bytes, then the format checks and the decoding. Both throw InputError as
/// readImageFile() does.
std::vector<unsigned char> readImageFileBytes(const std::string& path);
cv::Mat decodeImageFile(const std::vector<unsigned char>& bytes, const std::string& path,
                        int flags = cv::IMREAD_UNCHANGED);

/// Throws InputError naming `what` when the bytes of a JPEG or a PNG are
/// damaged as readImageFile() describes; other formats pass.
void checkImageBytes(const std::vector<unsigned char>& bytes, const std::string& what);
}  // namespace amcr
