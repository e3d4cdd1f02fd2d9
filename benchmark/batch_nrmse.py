#!/usr/bin/python3
"""NRMSE of a batch's views against exact references, view by view (relative to each reference's range).

    /usr/bin/python3 benchmark/batch_nrmse.py REFERENCE_PATTERN IMAGE_PATTERN N   (patterns with %d / %04d)

Prints the median, the worst view and its NRMSE, and the number of views above 2%.
"""
import sys

import numpy as np


def read_mha(path):
    data = open(path, "rb").read()
    header, _, body = data.partition(b"ElementDataFile = LOCAL\n")
    fields = dict(line.split(" = ", 1) for line in header.decode().splitlines() if " = " in line)
    size = [int(v) for v in fields["DimSize"].split()]
    return np.frombuffer(body, dtype="<f4", count=int(np.prod(size)))


def main():
    reference_pattern, image_pattern, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
    errors = []
    for k in range(count):
        reference = read_mha(reference_pattern % k).astype(np.float64)
        image = read_mha(image_pattern % k).astype(np.float64)
        span = reference.max() - reference.min()
        errors.append(np.sqrt(np.mean((image - reference) ** 2)) / span)
    errors = np.array(errors)
    worst = int(np.argmax(errors))
    print("views %d, NRMSE median %.4f, worst %.4f (view %d), above 2%%: %d"
          % (count, np.median(errors), errors[worst], worst, int(np.sum(errors > 0.02))))


if __name__ == "__main__":
    main()
