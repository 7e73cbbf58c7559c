"""Spark reads `protolink export`'s tables as they are, with the read the README shows
(`spark.read.option("mergeSchema", "true").parquet(DIR)`): per message type, the rows of four
captures equal `protolink decode --json`'s, value for value. Spark has no unsigned integers:
it widens uint8 to smallint and uint16 to int, so the values are the same."""

import os
import subprocess

import pytest

from test_export import count, equal, expected, expected_row, fleet, optional_exports, two_exports  # noqa: F401 (fixtures)
from conftest import PROTOLINK

pyspark_sql = pytest.importorskip("pyspark.sql")


@pytest.fixture(scope="module")
def spark():
    """A Spark session in this process's JVM, one core, bound to loopback, no web UI."""
    # Spark looks up the machine's own address unless told; the tests stay on loopback.
    os.environ.setdefault("SPARK_LOCAL_IP", "127.0.0.1")
    session = (pyspark_sql.SparkSession.builder.master("local[1]")
               .config("spark.ui.enabled", "false")
               .config("spark.driver.bindAddress", "127.0.0.1")
               .config("spark.driver.host", "127.0.0.1")
               .getOrCreate())
    session.sparkContext.setLogLevel("ERROR")
    yield session
    session.stop()


def test_spark_reads_the_export_as_it_is(fleet, spark, tmp_path):  # noqa: F811
    out = tmp_path / "tables"
    subprocess.run([PROTOLINK, "export", "--out", str(out), *map(str, fleet)], capture_output=True, check=True)
    want = expected(fleet)
    for name, rows in want.items():
        frame = spark.read.option("mergeSchema", "true").parquet(f"{out}/proto=*/type={name}")
        kinds = {f.name: "FLOAT" if f.dataType.simpleString() == "float" else f.dataType.simpleString()
                 for f in frame.schema.fields}
        got = [r.asDict() for r in frame.collect()]
        assert len(got) == len(rows), name
        for row, (source, e) in zip(got, rows):
            for column, value in expected_row(source, e, kinds).items():
                if column == "proto":
                    continue  # in the path, which a read of one table's directories leaves out
                assert column in row, (name, column)
                assert equal(row[column], value, kinds[column]), (name, column, row[column], value)
    # The README's kind of query, in Spark SQL: dotted names in backticks, one row per source.
    spark.read.option("mergeSchema", "true").parquet(f"{out}/proto=*/type=PRESSURE").createOrReplaceTempView("pressure")
    per_source = spark.sql("SELECT source, count(*) AS n, max(`meta.len`) AS len FROM pressure GROUP BY source")
    assert {r["source"]: r["n"] for r in per_source.collect()} == {
        str(p): sum(1 for s, _ in want["PRESSURE"] if s == str(p)) for p in fleet if "flight" in p.name}


def test_spark_reads_one_table_of_two_exports_through_one_glob(two_exports, spark):  # noqa: F811
    root, exports = two_exports
    everything = [p for sources in exports.values() for p in sources]
    frame = spark.read.option("mergeSchema", "true").parquet(f"{root}/*/proto=aeolus/type=GYRO")
    assert frame.count() == count(everything, "GYRO", "aeolus")
    assert frame.select("source").distinct().count() == 2


def test_spark_reads_exports_with_and_without_optional_fields_through_one_glob(optional_exports, spark):  # noqa: F811
    # No mergeSchema: the parts of both exports have one schema.
    root, exports = optional_exports
    frame = spark.read.parquet(f"{root}/*/proto=gdl90/type=OWNSHIP")
    assert frame.count() == count(exports["full"] + exports["bare"], "OWNSHIP", "gdl90")
    per_file = {r["file"]: r["n"] for r in frame.groupBy("file").agg({"`position.lat_deg`": "count"})
                .withColumnRenamed("count(position.lat_deg)", "n").collect()}
    assert per_file == {"bare-gdl90.pcapng": 0, "full-gdl90.pcapng": 2}


def test_spark_reads_box_time_and_lists(optional_exports, spark):  # noqa: F811
    # Spark reads Parquet's INT64 of a duration as a bigint of microseconds (it does not read
    # the Arrow schema the file keeps), and the AYDP lists as arrays of the items' types, full
    # and empty through one glob.
    root, _ = optional_exports
    gyro = spark.read.parquet(f"{root}/*/proto=aeolus/type=GYRO")
    kinds = {f.name: f.dataType.simpleString() for f in gyro.schema.fields}
    assert (kinds["box_time"], kinds["x_radps"]) == ("bigint", "float")
    fix = spark.read.parquet(f"{root}/*/proto=aydp/type=FIX_DETAIL")
    kinds = {f.name: f.dataType.simpleString() for f in fix.schema.fields}
    assert (kinds["satellites.id"], kinds["satellites.snr"]) == ("array<smallint>", "array<float>")
    rows = {r["file"]: (r["ids"], r["snr"]) for r in fix.selectExpr(
        "file", "`satellites.id` AS ids", "`satellites.snr` AS snr").collect()}
    assert rows == {"bare-aydp.pcapng": ([], []), "full-aydp.pcapng": ([7, 9], [38.0, 20.5])}
