"""Cyclone DDS (Python) types built from the `.msg` definitions mapc uses, so that Cyclone's
own CDR encoder and decoder run on exactly the fields mapc declares."""
import types
from dataclasses import dataclass

import cyclonedds.idl.types as t
from cyclonedds.idl import IdlStruct

PRIMITIVES = {
    "bool": bool, "int8": t.int8, "uint8": t.uint8, "int16": t.int16, "uint16": t.uint16,
    "int32": t.int32, "uint32": t.uint32, "int64": t.int64, "uint64": t.uint64,
    "float32": t.float32, "float64": t.float64, "string": str,
}


def full_name(short):
    pkg, name = short.split("/")
    return f"{pkg}/msg/{name}"


def dds_name(full):
    pkg, _, name = full.split("/")
    return f"{pkg}::msg::dds_::{name}_"


class Types:
    def __init__(self, definitions):
        self.definitions = definitions  # "pkg/msg/Name" -> .msg text
        self.classes = {}
        self.fields = {}

    def cls(self, full):
        if full in self.classes:
            return self.classes[full]
        fields = []
        for line in self.definitions[full].splitlines():
            typ, name = line.split()
            seq = typ.endswith("[]")
            base = typ[:-2] if seq else typ
            if base in PRIMITIVES:
                ann, sub = PRIMITIVES[base], None
            else:
                sub = full_name(base)
                ann = self.cls(sub)
            fields.append((name, t.sequence[ann] if seq else ann, seq, sub))
        annotations = {n: a for n, a, _, _ in fields}
        cls = types.new_class(
            full.split("/")[-1], (IdlStruct,), {"typename": dds_name(full)},
            lambda ns: ns.update({"__annotations__": annotations}))
        cls = dataclass(cls)
        self.classes[full] = cls
        self.fields[full] = fields
        return cls

    def value(self, full, data):
        """An instance of `full` from its JSON form (field names as in the .msg)."""
        cls = self.cls(full)
        args = {}
        for name, _, seq, sub in self.fields[full]:
            v = data[name]
            if sub is not None:
                v = [self.value(sub, x) for x in v] if seq else self.value(sub, v)
            args[name] = v
        return cls(**args)

    def plain(self, full, obj):
        """The JSON form of an instance."""
        self.cls(full)
        out = {}
        for name, _, seq, sub in self.fields[full]:
            v = getattr(obj, name)
            if sub is not None:
                v = [self.plain(sub, x) for x in v] if seq else self.plain(sub, v)
            elif seq:
                v = list(v)
            out[name] = v
        return out
