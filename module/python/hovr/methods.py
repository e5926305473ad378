"""The rendering methods hovr measures, behind one interface: one import for the registry of
methods (hovr.registry), the Renderer that draws them (hovr.renderer) and the error metrics
(hovr.metrics), so that ``from hovr import methods`` gives all three.
"""

from vtkmodules.vtkRenderingCore import vtkVolume

from .io import HovrError
from .metrics import compare, compare_blend, format_blend
from .registry import (
    BLEND_ARRAYS, BLEND_MODES, FLOAT_MAX, METHODS, AnalyticMethod, FixedPointMethod, Method,
    ObjectOrderMethod, PreIntegrationMethod, ReferenceMethod, StockMethod, ThreadedMethod,
    get_method)
from .renderer import MAX_SAMPLES_PER_RAY, RenderResult, Renderer, Scene

__all__ = [
    "BLEND_ARRAYS", "BLEND_MODES", "FLOAT_MAX", "MAX_SAMPLES_PER_RAY", "METHODS",
    "AnalyticMethod", "FixedPointMethod", "HovrError", "Method", "ObjectOrderMethod",
    "PreIntegrationMethod", "ReferenceMethod", "RenderResult", "Renderer", "Scene",
    "StockMethod", "ThreadedMethod", "compare", "compare_blend", "format_blend", "get_method",
    "vtkVolume"]
