# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""Writes ParaView's colour presets to a JSON file (a list of preset objects), so that
``hovr render --colormap NAME`` finds them by name without ParaView's Python.

    pvpython export_presets.py OUTPUT.json
"""
import json
import os
import sys

from paraview.modules.vtkRemotingViews import vtkSMTransferFunctionPresets


def main(path):
    presets = vtkSMTransferFunctionPresets.GetInstance()
    documents = [json.loads(presets.GetPresetAsString(i))
                 for i in range(presets.GetNumberOfPresets())]
    with open(path + ".partial", "w", encoding="utf-8") as stream:
        json.dump(documents, stream, indent=1)
    os.replace(path + ".partial", path)
    print("%d presets written to %s" % (len(documents), path))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
