"""map_server maps (a YAML and an image, as gmapping, slam_toolbox or cartographer save them): read
into free / occupied / unknown cells, and written from a mask. The rules are map_server's
(http://wiki.ros.org/map_server#YAML_format): a pixel's occupancy is p = (255 - v) / 255, or v / 255
with `negate: 1`, for the mean v of its colour channels; p > occupied_thresh is occupied, p <
free_thresh free, anything else (and a transparent pixel) unknown. `mode: raw` reads v itself as the
occupancy in percent (0-100; above 100 unknown). Row 0 of the image is the map's top edge (largest
y); `origin` is the pose of the bottom-left pixel's corner. Uses numpy and OpenCV."""
import math
import os

import cv2
import numpy as np

FREE, OCCUPIED, UNKNOWN = 0, 1, 2
DEFAULT_OCCUPIED_THRESH = 0.65  # map_server's defaults, as map_saver writes them
DEFAULT_FREE_THRESH = 0.196


class MapError(ValueError):
    """A map that cannot be read; the message names the file and what is wrong."""


class OccupancyMap:
    """cells[row, col] in {FREE, OCCUPIED, UNKNOWN}, row 0 at the bottom (y grows with the row)."""

    def __init__(self, cells, resolution, origin):
        self.cells, self.resolution, self.origin = cells, float(resolution), tuple(float(v) for v in origin)

    def to_world(self, col, row):
        """The world point (x, y) of a cell's (fractional) corner coordinates col, row."""
        x, y = col * self.resolution, row * self.resolution
        c, s = math.cos(self.origin[2]), math.sin(self.origin[2])
        return (self.origin[0] + c * x - s * y, self.origin[1] + s * x + c * y)

    def to_cell(self, x, y):
        """The (col, row) of the cell that holds the world point (x, y)."""
        dx, dy = x - self.origin[0], y - self.origin[1]
        c, s = math.cos(self.origin[2]), math.sin(self.origin[2])
        return (int(math.floor((c * dx + s * dy) / self.resolution)),
                int(math.floor((-s * dx + c * dy) / self.resolution)))


def _number(meta, key, path, default=None):
    if key not in meta:
        if default is None:
            raise MapError('%s: the key "%s" is missing' % (path, key))
        return default
    v = meta[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise MapError('%s: "%s" must be a number, got %r' % (path, key, v))
    return float(v)


def read_map(path):
    """The OccupancyMap of a map_server YAML file; MapError on anything that is not a valid map."""
    import yaml
    try:
        with open(path) as f:
            meta = yaml.safe_load(f)
    except OSError as e:
        raise MapError('%s: %s' % (path, e.strerror))
    except yaml.YAMLError as e:
        raise MapError('%s: not YAML: %s' % (path, e))
    if not isinstance(meta, dict):
        raise MapError('%s: not a map_server map (expected keys image, resolution, origin)' % path)
    if not isinstance(meta.get('image'), str) or not meta['image']:
        raise MapError('%s: the key "image" is missing or not a file name' % path)
    resolution = _number(meta, 'resolution', path)
    if resolution <= 0:
        raise MapError('%s: "resolution" must be positive (m per pixel), got %g' % (path, resolution))
    origin = meta.get('origin')
    if (not isinstance(origin, list) or len(origin) != 3 or
            not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in origin)):
        raise MapError('%s: "origin" must be [x, y, yaw], got %r' % (path, origin))
    occupied = _number(meta, 'occupied_thresh', path, DEFAULT_OCCUPIED_THRESH)
    free = _number(meta, 'free_thresh', path, DEFAULT_FREE_THRESH)
    if not 0.0 <= free < occupied <= 1.0:
        raise MapError('%s: need 0 <= free_thresh < occupied_thresh <= 1, got %g and %g' % (path, free, occupied))
    negate = meta.get('negate', 0)
    if negate not in (0, 1, True, False):
        raise MapError('%s: "negate" must be 0 or 1, got %r' % (path, negate))
    mode = meta.get('mode', 'trinary')
    if mode not in ('trinary', 'scale', 'raw'):
        raise MapError('%s: "mode" must be trinary, scale or raw, got %r' % (path, mode))
    image = meta['image'] if os.path.isabs(meta['image']) else os.path.join(os.path.dirname(os.path.abspath(path)), meta['image'])
    if not os.path.isfile(image):
        raise MapError('%s: the image "%s" does not exist (looked for %s)' % (path, meta['image'], image))
    pixels = cv2.imread(image, cv2.IMREAD_UNCHANGED)
    if pixels is None or pixels.size == 0:
        raise MapError('%s: the image %s cannot be read (PGM, PNG, BMP or JPEG expected)' % (path, image))
    return OccupancyMap(classify(pixels, negate, occupied, free, mode), resolution, origin)


def classify(pixels, negate, occupied_thresh, free_thresh, mode='trinary'):
    """FREE / OCCUPIED / UNKNOWN per pixel, flipped so that row 0 is the bottom row."""
    transparent = np.zeros(pixels.shape[:2], bool)
    if pixels.ndim == 3:
        if pixels.shape[2] == 4:
            transparent = pixels[:, :, 3] == 0
            pixels = pixels[:, :, :3]
        value = pixels.astype(np.float64).mean(axis=2)
    else:
        value = pixels.astype(np.float64)
    if pixels.dtype == np.uint16:
        value = value / 257.0
    cells = np.full(value.shape, UNKNOWN, np.uint8)
    if mode == 'raw':
        known = value <= 100.0
        cells[known & (value >= occupied_thresh * 100.0)] = OCCUPIED
        cells[known & (value <= free_thresh * 100.0)] = FREE
    else:
        p = value / 255.0 if negate else (255.0 - value) / 255.0
        cells[p > occupied_thresh] = OCCUPIED
        cells[p < free_thresh] = FREE
    cells[transparent] = UNKNOWN
    return cells[::-1].copy()


def write_map(path, cells, resolution, origin, image_name=None):
    """Writes a trinary map_server map (PGM: 0 occupied, 254 free, 205 unknown, as map_saver does)."""
    image_name = image_name or os.path.splitext(os.path.basename(path))[0] + '.pgm'
    pixels = np.full(cells.shape, 205, np.uint8)
    pixels[cells == FREE] = 254
    pixels[cells == OCCUPIED] = 0
    directory = os.path.dirname(os.path.abspath(path))
    if not cv2.imwrite(os.path.join(directory, image_name), pixels[::-1]):
        raise MapError('%s: cannot write the image %s' % (path, image_name))
    with open(path, 'w') as f:
        f.write('image: %s\nresolution: %g\norigin: [%g, %g, %g]\nnegate: 0\noccupied_thresh: %g\nfree_thresh: %g\n'
                % ((image_name, resolution) + tuple(origin) + (DEFAULT_OCCUPIED_THRESH, DEFAULT_FREE_THRESH)))
