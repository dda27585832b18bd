"""EDS text the boot interop scripts share (CiA 306, as a vendor tool
writes it): the communication objects every CiA 301 device describes
(1000h device type, 1001h error register, 1017h producer heartbeat time,
1018h identity sub 0-3) and CiA 302-3's 1F52h "verify application
software" (sub 1 the application software's date in days since 1 January
1984, sub 2 its time in ms after midnight), which a manager's software
check reads (CiA 302-2 section 4.4, against its 1F53h and 1F54h)."""


def comm_objects(device_type, vendor, product, revision, sub0_access="ro"):
    """The [1000], [1001], [1017] and [1018] sections of a device with this
    identity (1017h rw, default 0; 1018h sub 0 `sub0_access`)."""
    return f"""[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
DefaultValue=0x{device_type:08X}

[1001]
ParameterName=Error register
DataType=0x0005
AccessType=ro
DefaultValue=0

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=0

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=4

[1018sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType={sub0_access}
DefaultValue=3

[1018sub1]
ParameterName=Vendor-ID
DataType=0x0007
AccessType=ro
DefaultValue=0x{vendor:08X}

[1018sub2]
ParameterName=Product code
DataType=0x0007
AccessType=ro
DefaultValue=0x{product:02X}

[1018sub3]
ParameterName=Revision number
DataType=0x0007
AccessType=ro
DefaultValue=0x{revision:08X}
"""


def software_stamp(date, time_ms):
    """The [1F52] sections: the application software's date and time, read
    only."""
    return f"""[1F52]
ParameterName=Verify application software
ObjectType=0x8
SubNumber=3

[1F52sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=2

[1F52sub1]
ParameterName=Application software date
DataType=0x0007
AccessType=ro
DefaultValue={date}

[1F52sub2]
ParameterName=Application software time
DataType=0x0007
AccessType=ro
DefaultValue={time_ms}
"""
