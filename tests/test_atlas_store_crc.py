"""atlas_store.crc_of: the CRC-32 of a file's bytes, whatever its size (it reads through a map)."""

from __future__ import annotations

import zlib

import numpy as np
import pytest

from machdyn.synthesis.atlas_store import crc_of


@pytest.mark.parametrize("size", [0, 1, 4095, 4096, 3 * 2**20 + 7])
def test_crc_of_is_zlibs_crc_of_the_whole_file(tmp_path, size):
    data = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8).tobytes()
    file = tmp_path / "chunk.npy"
    file.write_bytes(data)
    assert crc_of(file) == zlib.crc32(data)
    # one byte changed anywhere (here the last) changes it
    if size:
        file.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))
        assert crc_of(file) != zlib.crc32(data)
