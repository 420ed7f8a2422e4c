# Copyright 2026 The anfis_elevation_ros Authors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""Declaring the parameters of core/params.py's table on a node, and validating changes."""

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rcl_interfaces.msg import SetParametersResult
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.parameter import Parameter

from ..core.errors import InputError
from ..core.params import is_ros_owned, node_specs, validate_value

_ROS_TYPES = {'bool': Parameter.Type.BOOL, 'int': Parameter.Type.INTEGER,
              'double': Parameter.Type.DOUBLE, 'string': Parameter.Type.STRING,
              'double_array': Parameter.Type.DOUBLE_ARRAY}


def parameter_descriptor(spec) -> ParameterDescriptor:
    """Build the ParameterDescriptor of a ParamSpec: type, description, range, read-only."""
    descriptor = ParameterDescriptor(name=spec.name, type=_ROS_TYPES[spec.kind].value,
                                     description=spec.description, read_only=spec.read_only)
    if spec.min_value is not None:
        if spec.kind == 'int':
            descriptor.integer_range = [IntegerRange(
                from_value=int(spec.min_value), to_value=int(spec.max_value), step=1)]
        elif spec.kind == 'double':
            descriptor.floating_point_range = [FloatingPointRange(
                from_value=float(spec.min_value), to_value=float(spec.max_value), step=0.0)]
        else:
            descriptor.additional_constraints = (
                f'each element in [{spec.min_value:g}, {spec.max_value:g}]')
    return descriptor


def declare_node_parameters(node, node_name: str) -> dict:
    """
    Declare every parameter of a node with its descriptor; return the validated values.

    Parameters
    ----------
    node : rclpy.node.Node
        The node (its overrides come from --params-file / -p).
    node_name : str
        ``IMU_NODE`` or ``CLASSIFIER_NODE`` (core.params).

    Raises
    ------
    InputError : an override of the wrong type or out of range.

    """
    values = {}
    for spec in node_specs(node_name).values():
        default = spec.default
        if spec.kind == 'double_array':
            default = list(default) if default else Parameter.Type.DOUBLE_ARRAY
        try:
            param = node.declare_parameter(spec.name, default, parameter_descriptor(spec))
        except InvalidParameterTypeException as err:
            hint = ' (write doubles with a decimal point, e.g. 400.0)' \
                if spec.kind in ('double', 'double_array') else ''
            raise InputError(f'parameter {spec.name}: {err}{hint}') from None
        except InvalidParameterValueException as err:
            raise InputError(f'parameter {spec.name}: {err}') from None
        values[spec.name] = validate_value(spec, param.value)
    return values


class LiveParameters:
    """
    Validates parameter changes on a running node and applies them.

    The on-set callback checks each new value against its ParamSpec, then calls
    ``check(values)`` with all values as they would be (it builds the core's dataclasses and
    raises InputError on inconsistent values); a refusal carries the reason. The post-set
    callback stores the values and calls ``apply(values, changed_names)``.

    Parameters
    ----------
    node : rclpy.node.Node
        The node, whose parameters are already declared.
    node_name : str
        ``IMU_NODE`` or ``CLASSIFIER_NODE``.
    values : dict
        Current values (from ``declare_node_parameters``).
    check : callable
        ``check(values)``, raising InputError when the set is unusable.
    apply : callable
        ``apply(values, changed)`` once accepted.

    """

    def __init__(self, node, node_name: str, values: dict, check, apply):
        self.values = dict(values)
        self._specs = node_specs(node_name)
        self._check = check
        self._apply = apply
        node.add_on_set_parameters_callback(self._on_set)
        node.add_post_set_parameters_callback(self._post_set)

    def _proposed(self, params) -> dict:
        values = dict(self.values)
        for param in params:
            spec = self._specs.get(param.name)
            if spec is None:
                if is_ros_owned(param.name):        # use_sim_time...: rclpy's business
                    continue
                raise InputError(f'{param.name} is not a parameter of this node')
            values[param.name] = validate_value(spec, param.value)
        return values

    def _on_set(self, params) -> SetParametersResult:
        try:
            self._check(self._proposed(params))
        except InputError as err:
            return SetParametersResult(successful=False, reason=str(err))
        return SetParametersResult(successful=True)

    def _post_set(self, params):
        changed = [p.name for p in params if p.name in self._specs]
        if changed:
            self.values = self._proposed(params)
            self._apply(self.values, changed)
