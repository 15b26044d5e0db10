// Foxglove's own client library (npm @foxglove/ws-protocol) against
// `dynapath web`: waits for the server's advertisement, subscribes to
// /report, decodes step reports (JSON) and checks them against the
// advertised JSON schema's fields. Usage:
//   NODE_PATH=DIR/node_modules node foxglove_client.js URL REPORTS
// Prints the last report; exit 1 on anything wrong.
"use strict";
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const WebSocket = require("ws");
const [url, wantedText] = process.argv.slice(2);
const wanted = Number(wantedText || 3);
const fail = (why) => { console.log("foxglove_client: " + why); process.exit(1); };
setTimeout(() => fail("timed out"), 120000);

const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
let schema = null, reports = 0, serverName = "";
client.on("serverInfo", (info) => { serverName = info.name; });
client.on("error", (e) => fail(String(e)));
client.on("advertise", (channels) => {
  const report = channels.find((c) => c.topic === "/report");
  if (!report) fail("no /report channel advertised");
  if (report.encoding !== "json" || report.schemaEncoding !== "jsonschema") fail("not JSON + JSON schema");
  schema = JSON.parse(report.schema);
  client.subscribe(report.id);
  console.log(`foxglove_client: ${serverName}: ${channels.map((c) => c.topic).join(" ")}; subscribed to /report`);
});
client.on("message", ({ data }) => {
  const message = JSON.parse(new TextDecoder().decode(data));
  for (const field of Object.keys(schema.properties)) {
    if (!(field in message)) fail("a report without " + field);
    const type = schema.properties[field].type;
    const ok = type === "string" ? typeof message[field] === "string" : Number.isFinite(message[field]);
    if (!ok) fail(`field ${field} is not a ${type}`);
  }
  if (message.success_rate < 0 || message.success_rate > 1) fail("success rate out of [0, 1]");
  if (++reports >= wanted) {
    console.log(`foxglove_client: ${reports} step reports; last: ${JSON.stringify(message)}`);
    client.close();
    process.exit(0);
  }
});
