# SPDX-License-Identifier: BSD-3-Clause
"""The server-manager XML mirrors the C++ classes: every documented default and range of a
property equals the class's own default and clamp range (via the Python-wrapped classes): the
XML min/max equal Get<X>MinValue()/Get<X>MaxValue() and setting beyond them clamps there."""
import os
import sys
import xml.etree.ElementTree as ElementTree

import shapediameter

xml = os.path.join(os.environ["SHAPEDIAMETER_SOURCE_DIR"], "Plugin", "ShapeDiameter.xml")
failures = []
checked = 0
for proxy in ElementTree.parse(xml).getroot().iter("SourceProxy"):
    cls = getattr(shapediameter, proxy.get("class"))
    if proxy.find("Documentation") is None:
        failures.append("%s has no documentation" % proxy.get("name"))
    for prop in list(proxy.iter("IntVectorProperty")) + list(proxy.iter("DoubleVectorProperty")):
        name = prop.get("name")
        if prop.find("Documentation") is None or not prop.find("Documentation").text.strip():
            failures.append("%s.%s has no documentation" % (proxy.get("name"), name))
        command = prop.get("command")
        if not command or not command.startswith("Set"):
            continue
        getter = "Get" + command[3:]
        instance = cls()
        cast = float if prop.tag == "DoubleVectorProperty" else int
        defaults = [cast(float(value)) for value in prop.get("default_values").split()]
        actual = getattr(instance, getter)()
        actuals = list(actual) if isinstance(actual, (tuple, list)) else [actual]
        if len(actuals) != len(defaults) or any(
                abs(a - d) > 1e-12 * max(1.0, abs(d)) for a, d in zip(actuals, defaults)):
            failures.append("%s.%s: XML default %r, C++ %r" % (proxy.get("name"), name, defaults, actuals))
        checked += 1
        domain = prop.find("IntRangeDomain")
        if domain is None:
            domain = prop.find("DoubleRangeDomain")
        if domain is None:
            continue
        for bound, probe in (("min", lambda v: v - 1 - abs(v)), ("max", lambda v: v + 1 + abs(v))):
            if domain.get(bound) is None:
                continue
            limit = cast(float(domain.get(bound)))
            # The clamp's own ends (vtkSetClampMacro's Get<X>MinValue / Get<X>MaxValue), which
            # Testing/Filters/TestParameterRanges.cxx compares with the core's Range constants.
            range_getter = "%s%sValue" % (getter, "Min" if bound == "min" else "Max")
            if not hasattr(instance, range_getter):
                failures.append("%s.%s: XML %s %r but C++ has no %s (not clamped)"
                                % (proxy.get("name"), name, bound, limit, range_getter))
            else:
                end = getattr(instance, range_getter)()
                if abs(end - limit) > 1e-12 * max(1.0, abs(limit)):
                    failures.append("%s.%s: XML %s %r, C++ %s() %r"
                                    % (proxy.get("name"), name, bound, limit, range_getter, end))
            getattr(instance, command)(cast(probe(limit)))
            clamped = getattr(instance, getter)()
            if abs(clamped - limit) > 1e-12 * max(1.0, abs(limit)):
                failures.append("%s.%s: XML %s %r, C++ clamps to %r" % (proxy.get("name"), name, bound, limit, clamped))
print("checked %d properties" % checked)
if failures:
    sys.exit("\n".join(failures))
